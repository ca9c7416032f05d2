"""What the tracker probes share: the halves, the pose reference and one pass that scores trackers' variants."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

#: camera -> (frames, ground truth, frames a second, the halves (first, last, step)).
DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 7.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def scored_half(bundle: Path, camera: str, first: int, last: int, step: int,
                trackers: dict[str, Tracker]) -> dict[str, list]:
    """Pose agreement with the reference (overall, people, people with left and right exchanged) of the bundle each
    frame on its own and through each tracker, all fed the same frames."""
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    scored: dict[str, list[ImageResult]] = {"each frame": [], **{name: [] for name in trackers}}
    theirs = []
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
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = [round(agreement.overall, 4), agreement.people, agreement.left_right_swapped]
    return readings
