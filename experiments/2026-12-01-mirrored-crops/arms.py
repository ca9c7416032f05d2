"""Each compile's bundle as shipped (control) against the same bundle read with each crop also read mirrored (frozen,
issue 57 item 4 and its pose acceptance figures). Two arms:

- "mirrored keypoint maps": the keypoint model (vc.deploy.crop_pose) reads each crop and its mirror image; the
  mirror's maps, flipped back and their pairs exchanged (image order), are averaged with the crop's before the peaks
  are taken. A mirror is the same person seen the other way round, so the two readings err independently where the
  model is unsure, and agree where it is sure.
- "and mirrored facing": the same, and the facing model's front logit, the head's and where the face points also
  averaged over the crop and its mirror (a mirror keeps a front a front and turns the face round).

Every reading runs in one process, frame by frame in turn (their times a ratio measured in one run), each frame on
its own and tracked as vc-eval tracks, scored against YOLO11n-pose @1280 as vc-eval scores pose.

    PYTHONPATH=src python experiments/2026-12-01-mirrored-crops/arms.py BUNDLE SEED CAMERA both|0|1 [ARM;ARM..] \
        >> experiments/2026-12-01-mirrored-crops/results/arms.jsonl

HALF 0 is the choosing half, 1 the confirming one; the arms are named in ARMS (by default the first two after the
control).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from vc.deploy.crop_pose import MAPS_OUTPUT, CropPoseReader, keypoints_of_maps
from vc.deploy.facing import (
    ACROSS_OUTPUT,
    FRAME_INPUT,
    HEAD_OUTPUT,
    OUTPUT_NAME,
    ROIS_INPUT,
    FacingReader,
    FacingReading,
    crop_rois,
    frame_part,
    front_logits,
)
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import PAIRS
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
_PAIR_ORDER = np.arange(17)
for _left, _right in PAIRS:
    _PAIR_ORDER[_left], _PAIR_ORDER[_right] = _right, _left


def mirrored(part: np.ndarray, rois: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A frame part (1, h, w, 3) mirrored left to right, and the rectangles (N, 4, pixel edges) that cut the same
    crops, mirrored, from it."""
    width = part.shape[2]
    flipped = np.ascontiguousarray(part[:, :, ::-1])
    return flipped, np.stack([width - rois[:, 2], rois[:, 1], width - rois[:, 0], rois[:, 3]], 1).astype(np.float32)


class MirroredCropPose(CropPoseReader):
    """The keypoint model's maps averaged over each crop and its mirror image."""

    def read(self, frame: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        if not len(boxes):
            return np.zeros((0, 17, 3), np.float64)
        rois = crop_rois(boxes)
        part, shifted = frame_part(frame, rois)
        maps = self.session.run([MAPS_OUTPUT], {FRAME_INPUT: part, ROIS_INPUT: shifted})[0]
        flipped, flipped_rois = mirrored(part, shifted)
        back = self.session.run([MAPS_OUTPUT], {FRAME_INPUT: flipped, ROIS_INPUT: flipped_rois})[0]
        back = back[:, _PAIR_ORDER, :, ::-1]  # the mirror's image-left member is the crop's image-right one
        return keypoints_of_maps((np.asarray(maps) + back) / 2.0, rois)


class MirroredFacing(FacingReader):
    """The facing model's readings averaged over each crop and its mirror image: the ``outputs`` named, for the
    people at least ``taller_than`` px tall."""

    def __init__(self, model: bytes, threads: int, outputs: tuple[str, ...], taller_than: float) -> None:
        super().__init__(model, threads)
        self.mirrored_outputs, self.taller_than = outputs, taller_than

    def read(self, frame: np.ndarray, boxes: np.ndarray) -> FacingReading:
        if not len(boxes):
            return super().read(frame, boxes)
        boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
        part, shifted = frame_part(frame, crop_rois(boxes))
        outputs = [OUTPUT_NAME] + [name for name, read in ((ACROSS_OUTPUT, self.reads_across),
                                                           (HEAD_OUTPUT, self.reads_head)) if read]
        found = dict(zip(outputs, self.session.run(outputs, {FRAME_INPUT: part, ROIS_INPUT: shifted}), strict=True))
        flipped, flipped_rois = mirrored(part, shifted)
        seen = dict(zip(outputs, self.session.run(outputs, {FRAME_INPUT: flipped, ROIS_INPUT: flipped_rois}),
                        strict=True))
        tall = boxes[:, 3] - boxes[:, 1] >= self.taller_than
        mean = {}
        for name in outputs:
            own = np.asarray(found[name], np.float64).reshape(-1)
            other = np.asarray(seen[name], np.float64).reshape(-1) * (-1.0 if name == ACROSS_OUTPUT else 1.0)
            mean[name] = np.where(tall & (name in self.mirrored_outputs), (own + other) / 2.0, own)
        return FacingReading(front_logits(mean[OUTPUT_NAME], mean.get(HEAD_OUTPUT), boxes[:, 3] - boxes[:, 1]),
                             mean.get(ACROSS_OUTPUT))


#: The readings: whether the keypoint maps are mirrored, the facing outputs mirrored, and from what height.
FRONT = (OUTPUT_NAME, HEAD_OUTPUT)
ARMS = {"control": (False, (), 0.0),
        "mirrored keypoint maps": (True, (), 0.0),
        "and mirrored facing": (True, FRONT + (ACROSS_OUTPUT,), 0.0),
        "and mirrored front": (True, FRONT, 0.0),
        "and mirrored face turn": (True, (ACROSS_OUTPUT,), 0.0),
        "and mirrored facing, 100 px and taller": (True, FRONT + (ACROSS_OUTPUT,), 100.0),
        "mirrored facing alone, 100 px and taller": (False, FRONT + (ACROSS_OUTPUT,), 100.0)}


def runtime(bundle: Path, keypoints: bool, facing: tuple[str, ...], taller_than: float) -> Runtime:
    run = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    threads = 1 if run.pool is not None else 2  # as the runtime gives each region's sessions
    for runner in run.runners:
        if keypoints and runner.crop_pose is not None:
            runner.crop_pose = MirroredCropPose(run.bundle.crop_pose, threads)
        if facing and runner.facing is not None:
            runner.facing = MirroredFacing(run.bundle.facing, threads, facing, taller_than)
    return run


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(bundle: Path, camera: str, first: int, last: int, step: int, arms: list[str]) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    runtimes = {name: runtime(bundle, *ARMS[name]) for name in arms}
    trackers = {name: Tracker(TrackingConfig()) for name in runtimes}
    scored: dict[str, list[ImageResult]] = {f"{name}, {mode}": [] for name in runtimes
                                            for mode in ("each frame", "tracked")}
    theirs: list[ImageResult] = []
    seconds: dict[str, list[float]] = {name: [] for name in runtimes}
    boxes_differ = 0
    try:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            results = {}
            for name, run in runtimes.items():
                start = time.perf_counter()
                results[name] = run.run(frame.image)
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
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    halves = DATA[camera][3] if sys.argv[4] == "both" else [DATA[camera][3][int(sys.argv[4])]]
    arms = ["control"] + (sys.argv[5].split(";") if len(sys.argv) > 5 else list(ARMS)[1:3])
    for first, last, step in halves:
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera,
                          **half(bundle, camera, first, last, step, arms)}), flush=True)


if __name__ == "__main__":
    main()
