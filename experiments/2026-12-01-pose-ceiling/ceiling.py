"""How far can pose agreement rise by facing alone? A bundle's people on one half, against YOLO11n-pose @1280 as
vc-eval compares them, with which way each person faces taken from the reference itself (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-12-01-pose-ceiling/ceiling.py BUNDLE CAMERA FIRST LAST STEP [FPS] >> OUT.jsonl

Four readings of the same people (those both detectors find at their operating points, vc.evaluation.agreement):

* ``as shipped``: the bundle's keypoints as it reports them;
* ``face turned by the reference``: the nose and eyes put ahead of the ears (vc.deploy.tracking.face_ahead) by the
  reference's own profile: across = sign(nose - ears' midpoint) where that is at least half the body model's
  nose-ahead distance, 0 otherwise (a three-way reading, the best a per-frame face-turn classifier could give);
* ``pairs in the reference's order``: each person's left/right pairs exchanged where more keypoints then agree
  (vc-eval's ``overall_if_left_right_matched``, person by person);
* ``both``.

With FPS the bundle's people are tracked over every frame from FIRST to LAST (vc-eval's tracked reading) and every
STEP-th is scored; without, each frame on its own. One JSON line: overall, per keypoint, people.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import FACE_AHEAD_OF_EARS, Tracker, TrackingConfig, face_ahead
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, matched_people, pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt")}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
NOSE, EARS = 0, [3, 4]


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


def reading(ours: list, theirs: list, turn: bool, order: bool) -> dict:
    images = []
    for mine, reference, my_matches, their_matches in zip(ours, theirs, matched_people(ours), matched_people(theirs),
                                                          strict=True):
        keypoints = mine.keypoints.copy()
        for truth in set(my_matches) & set(their_matches):
            person, ref = keypoints[my_matches[truth]], reference.keypoints[their_matches[truth]]
            height = mine.truth_boxes[truth][3] - mine.truth_boxes[truth][1]
            if order:
                confident = ref[:, 2] >= REFERENCE_CONFIDENCE
                exchanged = swap_pairs(person, [True] * len(PAIRS))
                agree = [(np.linalg.norm(k[:, :2] - ref[:, :2], axis=1)
                          <= AGREEMENT_HEAD_SIZES * HEAD_FRACTION_OF_HEIGHT * height)[confident].sum()
                         for k in (person, exchanged)]
                person = exchanged if agree[1] > agree[0] else person
            if turn and ref[NOSE, 2] >= REFERENCE_CONFIDENCE and ref[EARS, 2].max() >= REFERENCE_CONFIDENCE:
                ears = ref[EARS][ref[EARS, 2] >= REFERENCE_CONFIDENCE, 0].mean()
                ahead = (ref[NOSE, 0] - ears) / (FACE_AHEAD_OF_EARS["nose"] * height)
                box = mine.boxes[my_matches[truth]]
                person = face_ahead(person, float(box[3] - box[1]), 0.0 if abs(ahead) < 0.5 else float(np.sign(ahead)))
            keypoints[my_matches[truth]] = person
        images.append(ImageResult(truth_boxes=mine.truth_boxes, boxes=mine.boxes, scores=mine.scores,
                                  keypoints=keypoints))
    agreement = pose_agreement(images, theirs)
    return {"overall": round(agreement.overall, 4), "people": agreement.people,
            "per_keypoint": {name: round(value, 3) for name, value in agreement.per_keypoint().items()}}


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    frames = FrameRange(*map(int, sys.argv[3:6]))
    fps = float(sys.argv[6]) if len(sys.argv) > 6 else None
    ours, theirs = people_of(bundle, camera, frames, fps)
    readings = {"as shipped": (False, False), "face turned by the reference": (True, False),
                "pairs in the reference's order": (False, True), "both": (True, True)}
    print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": [frames.first, frames.last, frames.step],
                      "tracked_fps": fps, **{name: reading(ours, theirs, *how) for name, how in readings.items()}}))


if __name__ == "__main__":
    main()
