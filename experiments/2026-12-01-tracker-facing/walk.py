"""Does the tracker's facing from the walk still help once the facing and keypoint models read each frame? A
bundle as shipped, read once a frame and tracked twice: as vc-eval tracks (the walk orders each person's pairs
where it is clear, or where the networks are unsure), and with the walk never deciding. Pose agreement with
YOLO11n-pose @1280, each frame and both trackings (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-tracker-facing/walk.py BUNDLE tud|pets \
        >> experiments/2026-12-01-tracker-facing/results/walk.jsonl
"""

from __future__ import annotations

import json
import math
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 7.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
#: The walk never decides: no walk is clear enough, and no network unsure enough.
NO_WALK = replace(TrackingConfig(), min_significance=math.inf, trust_network=0.0)


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(bundle: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    trackers = {"tracked, the walk deciding": Tracker(TrackingConfig()), "tracked, the walk never": Tracker(NO_WALK)}
    scored: dict[str, list[ImageResult]] = {"each frame": [], **{name: [] for name in trackers}}
    theirs = []
    walk_decided = 0
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as runtime:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = runtime.run(frame.image)
            tracked = {name: result.reported(tracker.update(result.people, frame.number / fps, frame.image))
                       for name, tracker in trackers.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            scored["each frame"].append(_image(boxes, [p for p in result.people if not p.weak]))
            for name, people in tracked.items():
                scored[name].append(_image(boxes, people))
            walk_decided += sum(p.facing == "motion" for p in tracked["tracked, the walk deciding"])
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped}
    return {"frames": [first, last, step], "people_the_walk_faced": walk_decided, **readings}


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    for first, last, step in DATA[camera][3]:
        print(json.dumps({"bundle": str(bundle), "camera": camera, **half(bundle, camera, first, last, step)}),
              flush=True)


if __name__ == "__main__":
    main()
