"""Pose agreement with YOLO11n-pose @1280, each frame on its own and tracked, on both halves of a camera, for a bundle
as shipped and with its facing classifier's front logits taken from other models (frozen, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-pairs-in-profile/eval_arms.py BUNDLE CAMERA SEED [NAME=M[+M] ...] \
        >> results/arms.jsonl

An arm's models (train_arm.py's front.onnx, the classifier alone, or a bundle's facing model; several joined by
``+``, their logits averaged) replace the bundle's front logit for every person
the classifier reads (100 px and taller; smaller people are read by the head's colours), read as the runtime reads
it: people 100 px and taller twice, their crop and its mirror, averaged (vc.deploy.facing step 2). Everything else
is the bundle's and the runtime's as shipped, the tracker (decision 0044) included. Scored as vc-eval scores: the
people both detectors find at their operating points (vc.evaluation.agreement); each frame with the runtime's strong
people, tracked over every frame of the half at the camera's rate and scored every STEP-th frame. One JSON line per
arm and half.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import vc.deploy.runtime as runtime_module
from vc.deploy.engines import onnxruntime_inference
from vc.deploy.facing import (
    FRAME_INPUT,
    HEAD_READ_BELOW_PX,
    MIRRORED_FROM_PX,
    OUTPUT_NAME,
    ROIS_INPUT,
    FacingReader,
    FacingReading,
    crop_rois,
    frame_part,
    mirrored,
)
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 [(1, 200, 5), (201, 400, 5)], 7.0),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                [(1, 90, 1), (91, 179, 1)], 25.0)}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
HALVES = ("choosing", "confirming")


def reader_with(front_models: list[bytes] | None):
    """A FacingReader factory whose readers take the front logit of people the classifier reads from the mean of
    ``front_models``' (None: the bundle's own)."""

    class ArmReader(FacingReader):
        def __init__(self, model: bytes, threads: int = 1) -> None:
            super().__init__(model, threads)
            self.fronts = [onnxruntime_inference(model, threads) for model in front_models or []]

        def read(self, frame: np.ndarray, boxes: np.ndarray) -> FacingReading:
            reading = super().read(frame, boxes)
            if not self.fronts or not len(boxes):
                return reading
            boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
            heights = boxes[:, 3] - boxes[:, 1]
            read = heights >= HEAD_READ_BELOW_PX
            if not read.any():
                return reading
            rois = crop_rois(boxes[read])
            logits = self._front(*frame_part(frame, rois))
            tall = heights[read] >= MIRRORED_FROM_PX
            if tall.any():
                logits[tall] = (logits[tall] + self._front(*mirrored(*frame_part(frame, rois[tall])))) / 2.0
            front = reading.front_logits.copy()
            front[read] = logits
            return FacingReading(front, reading.across)

        def _front(self, part: np.ndarray, rois: np.ndarray) -> np.ndarray:
            return np.mean([np.asarray(front.run([OUTPUT_NAME], {FRAME_INPUT: part, ROIS_INPUT: rois})[0],
                                       np.float32).reshape(-1) for front in self.fronts], axis=0)

    return ArmReader


def scored(people: list, boxes: np.ndarray) -> ImageResult:
    return ImageResult(truth_boxes=boxes, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def main() -> None:
    bundle, camera, seed = Path(sys.argv[1]), sys.argv[2], int(sys.argv[3])
    arms = {"as shipped": None} | {name: [Path(path).read_bytes() for path in paths.split("+")] for name, paths in
                                   (arg.split("=", 1) for arg in sys.argv[4:])}
    video, gt, halves, fps = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    theirs = {half: [] for half in HALVES}
    for half, (first, last, step) in zip(HALVES, halves, strict=True):
        for frame in FrameSource(Path(video), FrameRange(first, last, step)):
            found = reference(frame.image)
            theirs[half].append(ImageResult(truth_boxes=truth.get(frame.number, np.zeros((0, 4))), boxes=found.boxes,
                                            scores=found.scores, keypoints=found.keypoints))
    for arm, model in arms.items():
        runtime_module.FacingReader = reader_with(model)
        for half, (first, last, step) in zip(HALVES, halves, strict=True):
            each, tracked = [], []
            with Runtime(bundle, threads=2) as runtime:
                for frame in FrameSource(Path(video), FrameRange(first, last, step)):
                    result = runtime.run(frame.image)
                    each.append(scored([p for p in result.people if not p.weak],
                                       truth.get(frame.number, np.zeros((0, 4)))))
            tracker = Tracker(TrackingConfig())
            with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as runtime:
                for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
                    result = runtime.run(frame.image)
                    people = result.reported(tracker.update(result.people, frame.number / fps, frame.image))
                    if (frame.number - first) % step == 0:
                        tracked.append(scored(people, truth.get(frame.number, np.zeros((0, 4)))))
            readings = {name: pose_agreement(ours, theirs[half]) for name, ours in
                        (("each frame", each), ("tracked", tracked))}
            print(json.dumps({"bundle": str(bundle), "camera": camera, "seed": seed, "arm": arm, "half": half,
                              **{name: {"overall": round(value.overall, 4), "people": value.people,
                                        "swapped": value.left_right_swapped}
                                 for name, value in readings.items()}}), flush=True)


if __name__ == "__main__":
    main()
