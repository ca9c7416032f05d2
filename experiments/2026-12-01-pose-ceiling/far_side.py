"""Which way TUD-Stadtmitte's people face, and whether the bundle's keypoints sit off the reference's by a shared
shift or by scatter: each frame on its own, one bundle, the confirming half (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-12-01-pose-ceiling/far_side.py BUNDLE > results/far_side_seed0.txt
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from ceiling import people_of

from vc.deploy.frames import FrameRange
from vc.evaluation.agreement import pose_agreement
from vc.keypoints import COCO_KEYPOINTS

ours, theirs = people_of(Path(sys.argv[1]), "tud", FrameRange(91, 179, 1), None)
agreement = pose_agreement(ours, theirs)
print("people", agreement.people, "left/right swapped", agreement.left_right_swapped)
print("median offset, ours - reference, head sizes (x right, y down), in the better order:")
for name, offset in zip(COCO_KEYPOINTS, agreement.median_offset, strict=True):
    print(f"  {name:15s} {offset[0]:+.2f} {offset[1]:+.2f}")
ahead = []
for reference in theirs:
    for points in reference.keypoints[reference.scores >= 0.5]:
        if points[0, 2] >= 0.5 and points[3:5, 2].max() >= 0.5:
            ears = points[3:5][points[3:5, 2] >= 0.5, 0].mean()
            ahead.append((points[0, 0] - ears) / (np.ptp(points[:, 1]) + 1.0))
ahead = np.array(ahead)
print(f"reference's nose against its ears, of {len(ahead)} people (score >= 0.5): left by > 0.03 heights "
      f"{(ahead < -0.03).mean():.2f}, right by > 0.03 {(ahead > 0.03).mean():.2f}")
