"""Is a person's left and right one question or one per pair? A bundle's people on one half against YOLO11n-pose
@1280, as vc-eval compares them, with their left/right pairs put in the reference's order for the whole person or
pair by pair, split by whether the reference sees the person in profile (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-12-02-pairs-in-profile/oracle.py BUNDLE CAMERA FIRST LAST STEP [FPS] >> OUT

The runtime orders all eight pairs of a person by one facing reading (vc.deploy.facing, step 3), from each pair's
image order. A person seen in profile has no image order for a pair: their near and far limbs cross as they walk.
Readings of the people both detectors find at their operating points (vc.evaluation.agreement):

* ``as shipped``;
* ``the person in the reference's order``: all pairs exchanged where more keypoints then agree (vc-eval's
  ``overall_if_left_right_matched``);
* ``each pair in the reference's order``: each pair exchanged where more of its two keypoints then agree;
* ``the trunk by the person, limbs by the pair``: eyes, ears, shoulders and hips by the person, elbows, wrists,
  knees and ankles pair by pair.

Each reading is scored over all people and over two groups: those the reference sees in profile (its nose ahead of
its ears' midpoint by at least half the body model's distance) and the others. With FPS the bundle's people are
tracked over every frame (vc-eval's tracked reading) and every STEP-th is scored; without, each frame on its own.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.facing import FACE_AHEAD_OF_EARS
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, matched_people
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt")}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
NOSE, EARS = 0, [3, 4]
#: Elbows, wrists, knees and ankles: the pairs a walk or a gesture crosses.
LIMB_PAIRS = [index for index, (left, _) in enumerate(PAIRS) if left in (7, 9, 13, 15)]


def people_of(bundle: Path, camera: str, frames: FrameRange, fps: float | None) -> tuple[list, list]:
    video, gt = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    tracker = Tracker(TrackingConfig()) if fps else None
    ours, theirs = [], []
    seen = FrameRange(frames.first, frames.last, 1) if fps else frames
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above if fps else None) as runtime:
        for frame in FrameSource(Path(video), seen):
            result = runtime.run(frame.image)
            if tracker:
                people = result.reported(tracker.update(result.people, frame.number / fps, frame.image))
                if (frame.number - frames.first) % frames.step:
                    continue
            else:
                people = [person for person in result.people if not person.weak]
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            ours.append(ImageResult(truth_boxes=boxes, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                                    scores=np.array([p.score for p in people]),
                                    keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3)))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    return ours, theirs


def agreeing(person: np.ndarray, ref: np.ndarray, reach: float) -> np.ndarray:
    """Per keypoint (17,): 1 agrees, 0 disagrees, -1 not compared (the reference unsure)."""
    near = np.linalg.norm(person[:, :2] - ref[:, :2], axis=1) <= reach
    return np.where(ref[:, 2] >= REFERENCE_CONFIDENCE, near.astype(int), -1)


def ordered(person: np.ndarray, ref: np.ndarray, reach: float, pairs: list[int] | None) -> np.ndarray:
    """``person`` with the pairs in ``pairs`` (None: all, as one) exchanged where more keypoints then agree."""
    if pairs is None:
        exchanged = swap_pairs(person, [True] * len(PAIRS))
        return exchanged if (agreeing(exchanged, ref, reach) == 1).sum() > (agreeing(person, ref, reach) == 1).sum() \
            else person
    person = person.copy()
    for index in pairs:
        mask = [i == index for i in range(len(PAIRS))]
        exchanged = swap_pairs(person, mask)
        members = list(PAIRS[index])
        if (agreeing(exchanged, ref, reach)[members] == 1).sum() > (agreeing(person, ref, reach)[members] == 1).sum():
            person = exchanged
    return person


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    frames = FrameRange(*map(int, sys.argv[3:6]))
    fps = float(sys.argv[6]) if len(sys.argv) > 6 else None
    ours, theirs = people_of(bundle, camera, frames, fps)
    trunk_pairs = [index for index in range(len(PAIRS)) if index not in LIMB_PAIRS]
    readings = {"as shipped": lambda p, r, s: p,
                "the person in the reference's order": lambda p, r, s: ordered(p, r, s, None),
                "each pair in the reference's order": lambda p, r, s: ordered(p, r, s, list(range(len(PAIRS)))),
                "the trunk by the person, limbs by the pair":
                    lambda p, r, s: ordered(_trunk_by_person(p, r, s, trunk_pairs), r, s, LIMB_PAIRS)}
    tallies = {name: {group: [0, 0] for group in ("all", "profile", "not in profile")} for name in readings}
    people = {"profile": 0, "not in profile": 0}
    for mine, reference, my_matches, their_matches in zip(ours, theirs, matched_people(ours), matched_people(theirs),
                                                          strict=True):
        for truth in set(my_matches) & set(their_matches):
            person, ref = mine.keypoints[my_matches[truth]], reference.keypoints[their_matches[truth]]
            height = mine.truth_boxes[truth][3] - mine.truth_boxes[truth][1]
            reach = AGREEMENT_HEAD_SIZES * HEAD_FRACTION_OF_HEIGHT * height
            ears = ref[EARS][ref[EARS, 2] >= REFERENCE_CONFIDENCE, 0]
            profile = (ref[NOSE, 2] >= REFERENCE_CONFIDENCE and len(ears) and
                       abs(ref[NOSE, 0] - ears.mean()) >= 0.5 * FACE_AHEAD_OF_EARS["nose"] * height)
            group = "profile" if profile else "not in profile"
            people[group] += 1
            for name, read in readings.items():
                agree = agreeing(read(person, ref, reach), ref, reach)
                for key in ("all", group):
                    tallies[name][key][0] += int((agree == 1).sum())
                    tallies[name][key][1] += int((agree >= 0).sum())
    print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": [frames.first, frames.last, frames.step],
                      "tracked_fps": fps, "people": people,
                      **{name: {group: round(agree / max(compared, 1), 4) for group, (agree, compared) in
                                groups.items()} for name, groups in tallies.items()}}))


def _trunk_by_person(person: np.ndarray, ref: np.ndarray, reach: float, trunk_pairs: list[int]) -> np.ndarray:
    """``person`` with every pair exchanged where more of the trunk's keypoints (eyes, ears, shoulders, hips) then
    agree."""
    members = [k for index in trunk_pairs for k in PAIRS[index]]
    exchanged = swap_pairs(person, [True] * len(PAIRS))
    return exchanged if (agreeing(exchanged, ref, reach)[members] == 1).sum() > \
        (agreeing(person, ref, reach)[members] == 1).sum() else person


if __name__ == "__main__":
    main()
