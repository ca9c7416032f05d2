"""Bundles that differ in their keypoint or facing model alone, read in one process frame by frame in turn (the
order rotated from frame to frame, their times a ratio measured in one run), each frame on its own and tracked as
vc-eval tracks, and scored against YOLO11n-pose @1280 as vc-eval scores pose (frozen experiment, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/measure.py CAMERA SEED 0|1 NAME=BUNDLE ... \
        >> RESULTS/arms.jsonl

CAMERA pets (every frame tracked at 10 frames/s, every 5th scored: 1-200 choosing, 201-400 confirming) or tud (25
frames/s, every frame: 1-90, 91-179); the first bundle is the control.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

CAMERAS = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                    10.0, ((1, 200, 5), (201, 400, 5))),
           "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt", 25.0,
                   ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(bundles: dict[str, Path], camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = CAMERAS[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    weak = TrackingConfig().weak_people_above
    runtimes = {name: Runtime(path, threads=2, weak_people_above=weak) for name, path in bundles.items()}
    trackers = {name: Tracker(TrackingConfig()) for name in runtimes}
    names = list(runtimes)
    scored: dict[str, list[ImageResult]] = {f"{name}, {mode}": [] for name in names
                                            for mode in ("each frame", "tracked")}
    theirs: list[ImageResult] = []
    seconds: dict[str, list[float]] = {name: [] for name in names}
    boxes_differ = 0
    try:
        for count, frame in enumerate(FrameSource(Path(video), FrameRange(first, last, 1))):
            results = {}
            for turn in range(len(names)):
                name = names[(count + turn) % len(names)]
                start = time.perf_counter()
                results[name] = runtimes[name].run(frame.image)
                seconds[name].append(time.perf_counter() - start)
            tracked = {name: results[name].reported(trackers[name].update(results[name].people, frame.number / fps,
                                                                          frame.image)) for name in names}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            for name in names:
                scored[f"{name}, each frame"].append(_image(boxes, [p for p in results[name].people if not p.weak]))
                scored[f"{name}, tracked"].append(_image(boxes, tracked[name]))
            found = [np.array([p.box for p in results[name].people]).reshape(-1, 4) for name in names]
            boxes_differ += int(any(not np.array_equal(found[0], other) for other in found[1:]))
            seen = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=seen.boxes, scores=seen.scores,
                                      keypoints=seen.keypoints))
    finally:
        for run in runtimes.values():
            run.close()
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped,
                          "per_keypoint": {k: round(v, 3) for k, v in agreement.per_keypoint().items()}}
    medians = {name: float(np.median(times)) for name, times in seconds.items()}
    return {"frames": [first, last, step], "frames_whose_boxes_differ": boxes_differ,
            "median_ms_a_frame": {name: round(1000 * value, 2) for name, value in medians.items()},
            "time_ratio": {name: round(value / medians[names[0]], 3) for name, value in medians.items()},
            "readings": readings}


def main() -> None:
    camera, seed, which = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    bundles = dict(argument.split("=", 1) for argument in sys.argv[4:])
    first, last, step = CAMERAS[camera][3][which]
    print(json.dumps({"seed": seed, "camera": camera, "bundles": bundles,
                      **half({name: Path(path) for name, path in bundles.items()}, camera, first, last, step)}),
          flush=True)


if __name__ == "__main__":
    main()
