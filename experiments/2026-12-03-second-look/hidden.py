"""Who the missed people in groups are (frozen experiment, issue 57 item 2): for each ground-truth person of
TUD-Stadtmitte overlapping another that the bundle's reported people miss at IoU 0.5, how much of them a nearer
person hides, the best IoU any reported person has with them, and whether a weak person (a centre peak below the
bundle's threshold, down to the tracker's 0.1) matches them, at what score.

    PYTHONPATH=src python experiments/2026-12-03-second-look/hidden.py BUNDLE FIRST LAST
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from analyse import matches

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.metrics import grouped
from vc.evaluation.mot import read_mot_boxes

VIDEO, GT = "../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt"


def hidden_share(truth: np.ndarray, index: int) -> float:
    """The share of truth box ``index`` covered by nearer people's boxes (feet lower in the image)."""
    box = truth[index]
    mask = np.zeros((int(box[3] - box[1]) + 1, int(box[2] - box[0]) + 1), bool)
    for other in truth:
        if other[3] > box[3]:
            x0, x1 = int(max(other[0] - box[0], 0)), int(max(min(other[2], box[2]) - box[0], 0))
            y0, y1 = int(max(other[1] - box[1], 0)), int(max(min(other[3], box[3]) - box[1], 0))
            mask[y0:y1, x0:x1] = True
    return float(mask.mean())


def main() -> None:
    bundle, first, last = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
    truth_by_frame = read_mot_boxes(Path(GT))
    runtime = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    try:
        for frame in FrameSource(Path(VIDEO), FrameRange(first, last, 1)):
            people = runtime.run(frame.image).people
            truth = truth_by_frame.get(frame.number, np.zeros((0, 4)))
            strong = [p for p in people if not p.weak]
            weak = [p for p in people if p.weak]
            boxes = np.array([p.box for p in strong]).reshape(-1, 4)
            ious = box_iou(boxes, truth) if len(boxes) else np.zeros((0, len(truth)))
            _, found = matches(ious, np.array([p.score for p in strong]))
            weak_ious = (box_iou(np.array([p.box for p in weak]), truth) if weak and len(truth)
                         else np.zeros((0, len(truth))))
            in_group = grouped(truth) if len(truth) else np.zeros(0, bool)
            for t in np.flatnonzero(in_group & ~found):
                best_weak = int(weak_ious[:, t].argmax()) if len(weak) else -1
                print(json.dumps({
                    "frame": frame.number, "height": round(float(truth[t, 3] - truth[t, 1]), 1),
                    "hidden": round(hidden_share(truth, t), 3),
                    "best_iou": round(float(ious[:, t].max()) if len(boxes) else 0.0, 3),
                    "weak_iou": round(float(weak_ious[best_weak, t]), 3) if best_weak >= 0 else 0.0,
                    "weak_score": round(float(weak[best_weak].score), 3) if best_weak >= 0 else None}),
                    flush=True)
    finally:
        runtime.close()


if __name__ == "__main__":
    main()
