"""Everyone the tracker reports each frame of a TUD-Stadtmitte half, as ``vc-serve`` reports them, by what they are:
seen this frame (strong), a weak peak continuing a track, or carried unseen (coasted); and by their best IoU with the
truth: matched (>= 0.5), near (0.3-0.5) or none (frozen experiment).

    PYTHONPATH=../../src python reported_kinds.py BUNDLE FIRST:LAST >> results/reported_kinds.jsonl

Why: the precision of everyone reported tracked is far below each frame's (0.60 against 0.88 at the operating
point on the choosing half); which of the tracker's additions cost it?
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.mot import read_mot_boxes

VIDEO = Path("../../../shared/data/tud_stadtmitte/frames")
GROUND_TRUTH = Path("../../../shared/data/tud_stadtmitte/gt_world.txt")
FPS = 25.0


def main() -> None:
    bundle, frames = Path(sys.argv[1]), sys.argv[2]
    truth = read_mot_boxes(GROUND_TRUTH)
    config = TrackingConfig()
    tracker = Tracker(config)
    counts: Counter[str] = Counter()
    with Runtime(bundle, threads=2, weak_people_above=config.weak_people_above) as runtime:
        for frame in FrameSource(VIDEO, FrameRange.parse(frames)):
            result = runtime.run(frame.image)
            people = result.reported(tracker.update(result.people, frame.number / FPS, frame.image))
            annotated = truth.get(frame.number, np.zeros((0, 4)))
            boxes = np.array([person.box for person in people]).reshape(-1, 4)
            best = (box_iou(boxes, annotated).max(axis=1) if len(annotated) and len(boxes)
                    else np.zeros(len(boxes)))
            for person, overlap in zip(people, best, strict=True):
                kind = "coasted" if person.coasted else "weak" if person.weak else "strong"
                counts[f"{kind}, {'matched' if overlap >= 0.5 else 'near' if overlap >= 0.3 else 'none'}"] += 1
                counts[f"{kind}, score under 0.3"] += person.score < 0.3
    print(json.dumps({"bundle": str(bundle), "frames": frames, "counts": dict(sorted(counts.items()))}))


if __name__ == "__main__":
    main()
