"""Each compile's bundle as shipped (control: the facing model and the keypoint model fp32, the facing model reading
tall people twice) against the same bundle with both at int8 (quantize.py), read as shipped and with the keypoint
model also reading each crop's mirror (../2026-12-01-mirrored-crops/arms.py's MirroredCropPose). Read in one
process, frame by frame in turn (their times a ratio measured in one run), each frame on its own and tracked as
vc-eval tracks, scored against YOLO11n-pose @1280 as vc-eval scores pose (frozen).

    PYTHONPATH=src python experiments/2026-12-01-int8-crop-models/arms.py CONTROL INT8_BUNDLE SEED CAMERA both|0|1 \
        >> experiments/2026-12-01-int8-crop-models/results/arms.jsonl
"""

from __future__ import annotations

import importlib.util
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

_SPEC = importlib.util.spec_from_file_location("mirrored_arms", Path(__file__).parents[1] / "2026-12-01-mirrored-crops"
                                               / "arms.py")
MIRRORED = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(MIRRORED)
DATA, REFERENCE = MIRRORED.DATA, MIRRORED.REFERENCE


def runtime(bundle: Path, keypoints_twice: bool) -> Runtime:
    run = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    threads = 1 if run.pool is not None else 2  # as the runtime gives each region's sessions
    for runner in run.runners:
        if keypoints_twice and runner.crop_pose is not None:
            runner.crop_pose = MIRRORED.MirroredCropPose(run.bundle.crop_pose, threads)
    return run


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(control: Path, int8: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    runtimes = {"control": runtime(control, False), "int8": runtime(int8, False),
                "int8, keypoints read twice": runtime(int8, True)}
    trackers = {name: Tracker(TrackingConfig()) for name in runtimes}
    scored: dict[str, list[ImageResult]] = {f"{name}, {mode}": [] for name in runtimes
                                            for mode in ("each frame", "tracked")}
    theirs: list[ImageResult] = []
    seconds: dict[str, list[float]] = {name: [] for name in runtimes}
    names = list(runtimes)
    boxes_differ = 0
    try:
        for count, frame in enumerate(FrameSource(Path(video), FrameRange(first, last, 1))):
            results = {}
            for turn in range(len(names)):  # the order rotated from frame to frame
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
            found_boxes = [np.array([p.box for p in results[name].people]).reshape(-1, 4) for name in names]
            boxes_differ += int(any(not np.array_equal(found_boxes[0], other) for other in found_boxes[1:]))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
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
            "time_ratio": {name: round(value / medians["control"], 3) for name, value in medians.items()},
            **readings}


def main() -> None:
    control, int8, seed, camera = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    halves = DATA[camera][3] if sys.argv[5] == "both" else [DATA[camera][3][int(sys.argv[5])]]
    for first, last, step in halves:
        print(json.dumps({"control": str(control), "int8": str(int8), "seed": seed, "camera": camera,
                          **half(control, int8, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
