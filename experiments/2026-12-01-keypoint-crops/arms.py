"""Each compile's bundle as shipped (control: the region networks' keypoints, with the facing model of 0027 and
0038) against the same bundle with the keypoint model (the arm: vc-train's ``vc.model.crop_pose``, trained on the
compile's renders with its seed), which reads each person's keypoints again from their crop. Both are read in one
pass over a half, frame by frame in turn (so that their times are a ratio measured in one run), each frame on its
own and tracked as vc-eval tracks, and scored against YOLO11n-pose @1280 as vc-eval scores pose (frozen, issue 57
item 4).

    PYTHONPATH=src python experiments/2026-12-01-keypoint-crops/arms.py CONTROL_BUNDLE RENDERS SEED CAMERA WORK \
        >> experiments/2026-12-01-keypoint-crops/results/arms.jsonl

WORK keeps the arm's run (RUN/crop_pose.onnx, crop_pose.json) and bundle; one JSON line per half.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from vc.deploy.bundle import MANIFEST, load_bundle
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes
from vc.keypoints import COCO_KEYPOINTS
from vc.model.export import with_crop_pose, write_bundle
from vc.stages.train import train_crop_pose_model

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 7.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"


def arm_bundle(control: Path, renders: Path, seed: int, work: Path) -> tuple[Path, dict]:
    """The control bundle with the keypoint model vc-train trains on the same renders with the same seed."""
    run, out = work / "run", work / "bundle"
    report = train_crop_pose_model(renders, run, seed, show_progress=False)
    if not (out / MANIFEST).is_file():
        manifest = json.loads((control / MANIFEST).read_text())
        files = {str(path.relative_to(control)): path.read_bytes() for path in control.rglob("*")
                 if path.is_file() and path.name != MANIFEST}
        manifest, files = with_crop_pose(manifest, files, run)
        write_bundle(manifest, files, out, as_zip=False)
    return out, report


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


#: The third reading: the keypoint model's keypoints but the region networks' wrists and ankles, the ends of the
#: limbs that the model read less often where the reference reads them on seed 0's choosing half (each frame and
#: tracked). Both runtimes find the same people in the same order (their boxes are checked equal), so it is scored
#: from the two runs without a third.
MIXED = "keypoint model, the networks' wrists and ankles"
ENDS = [COCO_KEYPOINTS.index(f"{side}_{part}") for part in ("wrist", "ankle") for side in ("left", "right")]


def mixed(model: ImageResult, control: ImageResult) -> ImageResult:
    assert np.array_equal(model.boxes, control.boxes)
    keypoints = model.keypoints.copy()
    keypoints[:, ENDS] = control.keypoints[:, ENDS]
    return ImageResult(truth_boxes=model.truth_boxes, boxes=model.boxes, scores=model.scores, keypoints=keypoints)


def half(bundles: dict[str, Path], camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    weak = TrackingConfig().weak_people_above
    runtimes = {name: Runtime(path, threads=2, weak_people_above=weak) for name, path in bundles.items()}
    trackers = {name: Tracker(TrackingConfig()) for name in bundles}
    scored: dict[str, list[ImageResult]] = {f"{name}, {mode}": [] for name in bundles
                                            for mode in ("each frame", "tracked")}
    theirs: list[ImageResult] = []
    seconds: dict[str, list[float]] = {name: [] for name in bundles}
    boxes_differ = 0
    try:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            results = {}
            for name, runtime in runtimes.items():
                start = time.perf_counter()
                results[name] = runtime.run(frame.image)
                seconds[name].append(time.perf_counter() - start)
            tracked = {name: result.reported(trackers[name].update(result.people, frame.number / fps, frame.image))
                       for name, result in results.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            for name, result in results.items():
                scored[f"{name}, each frame"].append(_image(boxes, [p for p in result.people if not p.weak]))
                scored[f"{name}, tracked"].append(_image(boxes, tracked[name]))
            found_boxes = [np.array([p.box for p in result.people]).reshape(-1, 4) for result in results.values()]
            boxes_differ += int(not np.array_equal(*found_boxes))  # the keypoint model moves keypoints alone
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    finally:
        for runtime in runtimes.values():
            runtime.close()
    for mode in ("each frame", "tracked"):
        scored[f"{MIXED}, {mode}"] = [mixed(model, control) for model, control in
                                      zip(scored[f"keypoint model, {mode}"], scored[f"control, {mode}"], strict=True)]
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped,
                          "per_keypoint": {k: round(v, 3) for k, v in agreement.per_keypoint().items()}}
    medians = {name: float(np.median(times)) for name, times in seconds.items()}
    return {"frames": [first, last, step], "frames_whose_boxes_differ": boxes_differ,
            "median_ms_a_frame": {name: round(1000 * value, 2) for name, value in medians.items()},
            "time_ratio": round(medians["keypoint model"] / medians["control"], 3), **readings}


def main() -> None:
    control, renders, seed, camera, work = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4], \
        Path(sys.argv[5])
    arm, report = arm_bundle(control, renders, seed, work)
    assert load_bundle(arm).crop_pose is not None, report
    for first, last, step in DATA[camera][3]:
        row = half({"control": control, "keypoint model": arm}, camera, first, last, step)
        print(json.dumps({"control": str(control), "seed": seed, "camera": camera,
                          "crop_pose": {k: v for k, v in report.items() if k != "trained_on"}, **row}), flush=True)


if __name__ == "__main__":
    main()
