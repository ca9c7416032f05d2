"""How clear must a walk be to decide which way a person faces, now that the facing model's vote over the track
orders everyone else (decision 0047)? Pose agreement with YOLO11n-pose @1280 tracked, both halves (frozen, issue 57).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted \
        python experiments/2026-12-02-walk-clarity/clarity.py BUNDLE SEED CAMERA >> results/arms.jsonl

The walk decides where the foot's speed is at least ``min_significance`` standard errors from zero, fitted over the
last ``window_s`` seconds (vc.deploy.tracking, step 3). Both were set when an unclear walk had no better cue than the
region networks, which hedge (0007). Since 0044 and 0047 the facing model's readings over 3 s order the people whose
walk is unclear, so a walk may need to be clearer to win. Each arm is the shipped tracker (main at 2f7b86a) with one
setting changed. Each frame runs once through the bundle as shipped; every arm's tracker is fed a copy of its
people. Data, reference and scoring are small-people-voted/arms.py's: PETS09 tracked at 10 frames/s (0046),
TUD-Stadtmitte at 25.
"""

from __future__ import annotations

import copy
import json
import sys
from collections.abc import Callable
from functools import partial
from pathlib import Path

import arms as voted  # experiments/2026-12-02-small-people-voted/arms.py
import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

#: arm -> the tracker's settings
ARMS = {"as shipped": TrackingConfig(),
        "a walk 3 standard errors clear": TrackingConfig(min_significance=3.0),
        "a walk 4 standard errors clear": TrackingConfig(min_significance=4.0),
        "a walk 6 standard errors clear": TrackingConfig(min_significance=6.0),
        "a walk fitted over 2 s": TrackingConfig(window_s=2.0)}


def half(bundle: Path, camera: str, first: int, last: int, step: int,
         arms: dict[str, Callable[[], Tracker]]) -> dict:
    """Each arm's pose agreement tracked over frames FIRST..LAST of CAMERA, every STEP-th scored; ``arms``: each arm's
    tracker factory."""
    video, gt, fps, _ = voted.DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(voted.REFERENCE), threads=2)
    trackers = {name: make() for name, make in arms.items()}
    scored: dict[str, list[ImageResult]] = {name: [] for name in arms}
    facing: dict[str, dict[str, int]] = {name: {} for name in arms}
    theirs: list[ImageResult] = []
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as run:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = run.run(frame.image)
            tracked = {name: result.reported(tracker.update(copy.deepcopy(result.people), frame.number / fps,
                                                            frame.image))
                       for name, tracker in trackers.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            for name, people in tracked.items():
                scored[name].append(voted._image(boxes, people))
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


def run(arms: dict[str, Callable[[], Tracker]]) -> None:
    """One JSON line per half of the command line's BUNDLE SEED CAMERA, every arm a tracker from its factory (also
    the other tracker experiments of 2026-12-02)."""
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    for name, (first, last, step) in zip(voted.HALVES, voted.DATA[camera][3], strict=True):
        readings = half(bundle, camera, first, last, step, arms)
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "frames": [first, last, step], **readings}), flush=True)


if __name__ == "__main__":
    run({name: partial(Tracker, config) for name, config in ARMS.items()})
