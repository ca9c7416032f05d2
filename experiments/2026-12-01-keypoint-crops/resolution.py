"""Does the keypoint model read real people better from crops at the resolution its training crops had? (frozen)

    PYTHONPATH=src python experiments/2026-12-01-keypoint-crops/resolution.py BUNDLE CROP_POSE.onnx CAMERA \
        FIRST LAST STEP >> results/resolution.jsonl

The model learns from crops cut out of the region renders, which are at the region network's input resolution
(PETS09's people about 40 px tall there, TUD-Stadtmitte's 60-105 px). Cut from a frame, a PETS09 person of 60-90 px
is sharper than anything it trained on. Each frame on its own, the bundle's people (as shipped, with its facing
model) are read three ways against YOLO11n-pose @1280: the bundle's keypoints; the model's from crops of the frame
(what the runtime does); the model's from crops of the frame resized as the person's region network resizes it
(each axis by the region's input over its crop window), mapped back. Two more: the mean of the bundle's and the
model's (frame crops) places, and the model's where its heat map's peak is at least a floor (0.2-0.5), the bundle's
elsewhere.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import cv2
import numpy as np

from vc.deploy.crop_pose import CropPoseReader, with_crop_keypoints
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt")}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
PEAK_FLOORS = (0.2, 0.3, 0.4, 0.5)


def at_region_resolution(reader: CropPoseReader, frame: np.ndarray, boxes: np.ndarray,
                         scale: np.ndarray) -> np.ndarray:
    height, width = frame.shape[:2]
    small = cv2.resize(frame, (max(1, round(width * scale[0])), max(1, round(height * scale[1]))),
                       interpolation=cv2.INTER_AREA)
    factor = np.array([small.shape[1] / width, small.shape[0] / height])
    scaled = (boxes.reshape(-1, 2, 2) + 0.5) * factor - 0.5
    read = reader.read(small, scaled.reshape(-1, 4))
    read[..., :2] = (read[..., :2] + 0.5) / factor - 0.5
    return read


def main() -> None:
    bundle, model, camera = Path(sys.argv[1]), Path(sys.argv[2]).read_bytes(), sys.argv[3]
    frames = FrameRange(*map(int, sys.argv[4:7]))
    video, gt = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    reader = CropPoseReader(model, threads=2)
    names = ("bundle", "model, frame crops", "model, region-resolution crops", "mean of the bundle and the model",
             *(f"the model where its peak is at least {floor}" for floor in PEAK_FLOORS))
    ours: dict[str, list[ImageResult]] = {name: [] for name in names}
    theirs = []
    with Runtime(bundle, threads=2) as runtime:
        scales = {runner.entry.name: runner.scale for runner in runtime.runners}
        for frame in FrameSource(Path(video), frames):
            people = [person for person in runtime.run(frame.image).people if not person.weak]
            boxes = np.array([person.box for person in people]).reshape(-1, 4)
            shipped = np.array([person.keypoints for person in people]).reshape(-1, 17, 3)
            readings = {"bundle": shipped,
                        "model, frame crops": reader.read(frame.image, boxes),
                        "model, region-resolution crops": np.array(
                            [at_region_resolution(reader, frame.image, person.box[None], scales[person.region])[0]
                             for person in people]).reshape(-1, 17, 3)}
            for name, read in readings.items():
                keypoints = shipped.copy() if name == "bundle" else np.array(
                    [with_crop_keypoints(person.keypoints, points, person.pair_handedness)
                     for person, points in zip(people, read, strict=True)]).reshape(-1, 17, 3)
                if name == "model, frame crops":
                    mean = keypoints.copy()
                    mean[..., :2] = (keypoints[..., :2] + shipped[..., :2]) / 2
                    ours["mean of the bundle and the model"].append(ImageResult(
                        truth_boxes=truth.get(frame.number, np.zeros((0, 4))), boxes=boxes,
                        scores=np.array([p.score for p in people]), keypoints=mean))
                    peaks = np.array([with_crop_keypoints(person.keypoints, points[:, [2, 2, 2]],
                                                          person.pair_handedness)[:, 0]
                                      for person, points in zip(people, read, strict=True)]).reshape(-1, 17)
                    for floor in PEAK_FLOORS:
                        gated = np.where((peaks >= floor)[..., None], keypoints, shipped)
                        ours[f"the model where its peak is at least {floor}"].append(ImageResult(
                            truth_boxes=truth.get(frame.number, np.zeros((0, 4))), boxes=boxes,
                            scores=np.array([p.score for p in people]), keypoints=gated))
                ours[name].append(ImageResult(truth_boxes=truth.get(frame.number, np.zeros((0, 4))), boxes=boxes,
                                              scores=np.array([p.score for p in people]), keypoints=keypoints))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=truth.get(frame.number, np.zeros((0, 4))), boxes=found.boxes,
                                      scores=found.scores, keypoints=found.keypoints))
    out = {"bundle": str(bundle), "camera": camera, "frames": [frames.first, frames.last, frames.step]}
    for name, images in ours.items():
        agreement = pose_agreement(images, theirs)
        out[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                     "per_keypoint": {k: round(v, 3) for k, v in agreement.per_keypoint().items()}}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
