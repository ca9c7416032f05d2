"""Should the track's vote of the facing model (decision 0044) also order people under 100 px whose walk is unclear?
Pose agreement with YOLO11n-pose @1280 tracked, on both halves of a camera (frozen, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-small-people-voted/arms.py BUNDLE SEED CAMERA >> results/arms.jsonl

Since 0044 the tracker keeps the facing model's readings of people 100 px and taller (read twice,
vc.deploy.tracking.model_reading), and where such a person's walk is unclear, not a walk or too short to tell, the
last 3 s of readings order their pairs. Smaller people, read once (by the head's colours, 0041), are ordered by
their walk even where it is unclear, unless the region networks are confident. Each arm is the shipped tracker with
``model_reading`` keeping the readings of people from ARM's height up, and its vote over ARM's seconds:

* ``as shipped``: 100 px, 3 s;
* ``everyone, a 3 s vote`` and ``everyone, a 1 s vote``: every person the facing model read;
* ``everyone, 1 s under 100 px, 3 s from 100 px``: every person, the vote over 1 s for people under 100 px when
  they are seen, over 3 s for the others.

Each frame runs once through the bundle as shipped; every arm's tracker is fed a copy of its people. Scored as
vc-eval scores pose (vc.evaluation.agreement), every STEP-th frame of the half. One JSON line per half.
"""

from __future__ import annotations

import copy
import json
import sys
from pathlib import Path

import numpy as np

import vc.deploy.tracking as tracking
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Person, Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

#: PETS09 is tracked at the rate vc-eval reads from vtest.avi, 10 frames/s (earlier experiments tracked it at 7).
DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 10.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
HALVES = ("choosing", "confirming")
#: arm -> (the height from which readings are kept, px; the vote's seconds)
ARMS = {"as shipped": (100.0, 3.0), "everyone, a 3 s vote": (0.0, 3.0), "everyone, a 1 s vote": (0.0, 1.0),
        "everyone, 1 s under 100 px, 3 s from 100 px": (0.0, None)}
SHIPPED_BY_VOTE = tracking._by_vote


def by_vote_for_size(person: Person, track, vote_s: float) -> Person:
    """``vc.deploy.tracking._by_vote`` over 1 s for people under 100 px, 3 s for the others."""
    return SHIPPED_BY_VOTE(person, track, 1.0 if person.box[3] - person.box[1] < 100.0 else 3.0)


def reading_from(height_px: float):
    """``vc.deploy.tracking.model_reading`` keeping the readings of people ``height_px`` and taller."""

    def model_reading(person: Person) -> float | None:
        if person.network_handedness is None or person.box[3] - person.box[1] < height_px:
            return None
        return person.handedness

    return model_reading


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(bundle: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    trackers = {name: Tracker(TrackingConfig(facing_vote_s=vote_s or 3.0)) for name, (_, vote_s) in ARMS.items()}
    scored: dict[str, list[ImageResult]] = {name: [] for name in ARMS}
    facing: dict[str, dict[str, int]] = {name: {} for name in ARMS}
    theirs: list[ImageResult] = []
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as run:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = run.run(frame.image)
            tracked = {}
            for name, tracker in trackers.items():
                tracking.model_reading = reading_from(ARMS[name][0])
                tracking._by_vote = SHIPPED_BY_VOTE if ARMS[name][1] else by_vote_for_size
                tracked[name] = result.reported(tracker.update(copy.deepcopy(result.people), frame.number / fps,
                                                               frame.image))
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            for name, people in tracked.items():
                scored[name].append(_image(boxes, people))
                for person in people:
                    facing[name][person.facing] = facing[name].get(person.facing, 0) + 1
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped, "facing": facing[name]}
    return readings


def main() -> None:
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    for name, (first, last, step) in zip(HALVES, DATA[camera][3], strict=True):
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "frames": [first, last, step], **half(bundle, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
