"""The people a side of the frame cuts in TUD-Stadtmitte's frames, each frame on its own: which side, their width over
height, their height, and the best IoU of a person the bundle reports, as shipped (frozen experiment, decision 0031).

    PYTHONPATH=../.. python cut_misses.py BUNDLE 1:90 > results/cut_misses_tud_seed0.txt

A best IoU under 0.5 is a miss; 0.3–0.5 a near miss (vc.evaluation.misses).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.mot import read_mot_boxes

TUD = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "tud_stadtmitte"
WIDTH = 640
#: A box within this many pixels of a side is cut by it (vc.evaluation.misses.CUT_PX).
CUT_PX = 2.0


def main() -> None:
    bundle, frames = Path(sys.argv[1]), FrameRange.parse(sys.argv[2])
    truth = read_mot_boxes(TUD / "gt_world.txt")
    print("frame side width/height height_px best_iou")
    with Runtime(bundle, threads=1) as runtime:
        for frame in FrameSource(TUD / "frames", frames):
            boxes = np.array([person.box for person in runtime.run(frame.image).people]).reshape(-1, 4)
            for box in truth.get(frame.number, np.zeros((0, 4))):
                left, right = box[0] <= CUT_PX - 0.5, box[2] >= WIDTH - 0.5 - CUT_PX
                if not (left or right):
                    continue
                best = float(box_iou(box[None], boxes).max()) if len(boxes) else 0.0
                print(frame.number, "left" if left else "right", round((box[2] - box[0]) / (box[3] - box[1]), 2),
                      round(box[3] - box[1]), round(best, 2))


if __name__ == "__main__":
    main()
