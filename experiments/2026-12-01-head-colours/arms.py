"""Each compile's bundle as shipped (control) against the same bundle whose facing model also reads front from behind
by the head's colours, for people under the runtime's gate (the arm: vc-train's facing model since decision 0041,
trained on the compile's renders with its seed; its classifier and face turn are bit for bit the control's). Both
are read in one pass over a half, each frame on its own and tracked as vc-eval tracks, and scored against
YOLO11n-pose @1280 as vc-eval scores pose (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-12-01-head-colours/arms.py CONTROL_BUNDLE RENDERS SEED CAMERA WORK \
        [CLASSIFIER_WEIGHT [HALF]] >> experiments/2026-12-01-head-colours/results/arms.jsonl

CLASSIFIER_WEIGHT: the classifier's share beside the head's (vc.deploy.facing.CLASSIFIER_WEIGHT_BELOW) for this
run; HALF: 0 (choosing) or 1 (confirming), both by default. WORK keeps the arm's run and bundle; one JSON line per
half.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import vc.deploy.facing as facing
from vc.deploy.bundle import MANIFEST, load_bundle
from vc.deploy.facing import FacingReader
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes
from vc.model.export import with_facing, write_bundle
from vc.stages.train import train_facing_model

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 7.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"


def arm_bundle(control: Path, renders: Path, seed: int, work: Path) -> tuple[Path, dict]:
    """The control bundle with the facing model vc-train now trains on the same renders with the same seed."""
    run, out = work / "run", work / "bundle"
    report = train_facing_model(renders, run, seed, show_progress=False)
    if not (out / MANIFEST).is_file():
        manifest = json.loads((control / MANIFEST).read_text())
        files = {str(path.relative_to(control)): path.read_bytes() for path in control.rglob("*")
                 if path.is_file() and path.name != MANIFEST}
        manifest, files = with_facing(manifest, files, run)
        write_bundle(manifest, files, out, as_zip=False)
    return out, report


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


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
    front_difference = 0.0
    try:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            results = {name: runtime.run(frame.image) for name, runtime in runtimes.items()}
            tracked = {name: result.reported(trackers[name].update(result.people, frame.number / fps, frame.image))
                       for name, result in results.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            for name, result in results.items():
                scored[f"{name}, each frame"].append(_image(boxes, [p for p in result.people if not p.weak]))
                scored[f"{name}, tracked"].append(_image(boxes, tracked[name]))
            pairs = [np.array([p.pair_handedness for p in result.people
                               if not p.weak and p.pair_handedness is not None]) for result in results.values()]
            if len(pairs[0]) and pairs[0].shape == pairs[1].shape:  # the facing read alike by both arms
                front_difference = max(front_difference, float(np.abs(pairs[0] - pairs[1]).max()))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    finally:
        for runtime in runtimes.values():
            runtime.close()
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped,
                          "per_keypoint": {k: round(v, 3) for k, v in agreement.per_keypoint().items()}}
    return {"frames": [first, last, step], "pair_handedness_max_difference": round(front_difference, 6), **readings}


def main() -> None:
    control, renders, seed, camera, work = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4], \
        Path(sys.argv[5])
    if len(sys.argv) > 6:
        facing.CLASSIFIER_WEIGHT_BELOW = float(sys.argv[6])
    halves = DATA[camera][3] if len(sys.argv) <= 7 else [DATA[camera][3][int(sys.argv[7])]]
    arm, report = arm_bundle(control, renders, seed, work)
    assert FacingReader(load_bundle(arm).facing).reads_head
    for first, last, step in halves:
        row = half({"control": control, "head colours": arm}, camera, first, last, step)
        print(json.dumps({"control": str(control), "seed": seed, "camera": camera,
                          "classifier_weight_below": facing.CLASSIFIER_WEIGHT_BELOW,
                          "head_colours": report.get("head_colours"), **row}), flush=True)


if __name__ == "__main__":
    main()
