"""Every person a bundle reports on TUD-Stadtmitte's frames, with what its keypoint model reads at both sides of the
person's box (a crop as wide as one person, at the box's left and at its right), beside the ground truth: the
features a "second look" at boxes over two people would decide on (frozen experiment, issue 57 item 2).

    PYTHONPATH=src python experiments/2026-12-03-second-look/dump.py BUNDLE FIRST LAST > RESULTS/people_SEED_HALF.jsonl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.crop_pose import CropPoseReader
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.mot import read_mot_boxes

VIDEO, GT = "../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt"
#: The width of one person's candidate crop, in the box's heights.
ASPECT = 0.4


def sides(boxes: np.ndarray, aspect: float = ASPECT) -> np.ndarray:
    """Boxes (2N, 4) one person wide at the left and the right of each of ``boxes`` (N, 4), as tall."""
    width = aspect * (boxes[:, 3] - boxes[:, 1])
    left = np.stack([boxes[:, 0], boxes[:, 1], boxes[:, 0] + width, boxes[:, 3]], axis=1)
    right = np.stack([boxes[:, 2] - width, boxes[:, 1], boxes[:, 2], boxes[:, 3]], axis=1)
    return np.concatenate([left, right])


def main() -> None:
    bundle, first, last = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
    truth = read_mot_boxes(Path(GT))
    runtime = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    reader = CropPoseReader(runtime.bundle.crop_pose, 2)
    try:
        for frame in FrameSource(Path(VIDEO), FrameRange(first, last, 1)):
            people = [p for p in runtime.run(frame.image).people if not p.weak]
            boxes = np.array([p.box for p in people]).reshape(-1, 4)
            gt = truth.get(frame.number, np.zeros((0, 4)))
            ious = box_iou(boxes, gt) if len(boxes) and len(gt) else np.zeros((len(boxes), len(gt)))
            readings = reader.read(frame.image, sides(boxes)) if len(boxes) else np.zeros((0, 17, 3))
            print(json.dumps({
                "frame": frame.number, "truth": np.round(gt, 1).tolist(),
                "people": [{"box": np.round(p.box, 1).tolist(), "score": round(float(p.score), 4),
                            "region": p.region, "keypoints": np.round(p.keypoints, 2).tolist(),
                            "ious": np.round(ious[i], 3).tolist(),
                            "left": np.round(readings[i], 2).tolist(),
                            "right": np.round(readings[len(people) + i], 2).tolist()}
                           for i, p in enumerate(people)]}), flush=True)
    finally:
        runtime.close()


if __name__ == "__main__":
    main()
