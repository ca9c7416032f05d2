"""Which people is the keypoint model worth reading? Its keypoints replace the region networks' only for people at
least GATE px tall in the frame, the networks' stand elsewhere; how often each reading agrees with YOLO11n-pose
@1280, each frame on its own, and what share of the people each gate reads (the model's time is per person read)
(frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-keypoint-model-cost/gate.py BUNDLE CROP_POSE.onnx CAMERA \
        FIRST LAST STEP >> results/gate.jsonl

BUNDLE is a compile's bundle as shipped (without the keypoint model); CROP_POSE.onnx the keypoint model trained on
the same compile's renders; the model is read with the runtime's floor (vc.deploy.crop_pose.PEAK_FLOOR), and at
the gate of 100 px also with other floors (a model trained with another loss may be sure more often).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import vc.deploy.crop_pose
from vc.deploy.crop_pose import PEAK_FLOOR, CropPoseReader, with_crop_keypoints
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt")}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
GATES = (0, 60, 80, 100, 120, 150, 200, 10_000)  # px; 10 000: nobody is read (the bundle as shipped)
FLOORS = (0.0, 0.3, 0.5, 0.7)  # at the gate of 100 px


def main() -> None:
    bundle, model, camera = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    frames = FrameRange(*map(int, sys.argv[4:7]))
    video, gt = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    reader = CropPoseReader(model.read_bytes(), threads=2)
    ours: dict[int, list[ImageResult]] = {gate: [] for gate in GATES}
    by_floor: dict[float, list[ImageResult]] = {floor: [] for floor in FLOORS}
    read_by_gate = dict.fromkeys(GATES, 0)
    people_seen = 0
    theirs = []
    with Runtime(bundle, threads=2) as runtime:
        for frame in FrameSource(Path(video), frames):
            people = [person for person in runtime.run(frame.image).people if not person.weak]
            boxes = np.array([person.box for person in people]).reshape(-1, 4)
            heights = boxes[:, 3] - boxes[:, 1]
            shipped = np.array([person.keypoints for person in people]).reshape(-1, 17, 3)
            raw = reader.read(frame.image, boxes)
            model_read = np.array([with_crop_keypoints(person.keypoints, points, person.pair_handedness)
                                   for person, points in zip(people, raw, strict=True)]).reshape(-1, 17, 3)
            boxes_truth = truth.get(frame.number, np.zeros((0, 4)))
            read_at_100 = heights >= 100
            for floor in FLOORS:
                vc.deploy.crop_pose.PEAK_FLOOR = floor
                floored = np.array([with_crop_keypoints(person.keypoints, points, person.pair_handedness)
                                    for person, points in zip(people, raw, strict=True)]).reshape(-1, 17, 3)
                by_floor[floor].append(ImageResult(
                    truth_boxes=boxes_truth, boxes=boxes, scores=np.array([p.score for p in people]),
                    keypoints=np.where(read_at_100[:, None, None], floored, shipped)))
            vc.deploy.crop_pose.PEAK_FLOOR = PEAK_FLOOR
            people_seen += len(people)
            for gate in GATES:
                read = heights >= gate
                read_by_gate[gate] += int(read.sum())
                ours[gate].append(ImageResult(truth_boxes=boxes_truth, boxes=boxes,
                                              scores=np.array([p.score for p in people]),
                                              keypoints=np.where(read[:, None, None], model_read, shipped)))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes_truth, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    out = {"bundle": str(bundle), "model": str(model), "camera": camera,
           "frames": [frames.first, frames.last, frames.step], "people": people_seen, "gates": {}}
    for gate, images in ours.items():
        agreement = pose_agreement(images, theirs)
        out["gates"][str(gate)] = {"overall": round(agreement.overall, 4), "scored": agreement.people,
                                   "share_read": round(read_by_gate[gate] / max(people_seen, 1), 3)}
    out["floors_at_100_px"] = {str(floor): round(pose_agreement(images, theirs).overall, 4)
                               for floor, images in by_floor.items()}
    print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
