"""Precision and recall of everyone a bundle reports each frame (every person at or above the decoder's threshold, as
the appliance reports them), today's bundle against the behind bundle at T, on TUD-Stadtmitte's halves (frozen
experiment, issue 57 item 2).

    PYTHONPATH=src:experiments/2026-12-03-second-person python experiments/2026-12-03-second-person/reported.py \
        TODAY BEHIND T [T ...]

AP50 ranks people by score and so forgives low-scored false ones; an appliance reports them all.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import real
import second_person

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.mot import read_mot_boxes

VIDEO = Path("../shared/data/tud_stadtmitte/frames")
GROUND_TRUTH = Path("../shared/data/tud_stadtmitte/gt_world.txt")
HALVES = {"choosing": (1, 90), "confirming": (91, 179)}


def main() -> None:
    today, behind = Path(sys.argv[1]), Path(sys.argv[2])
    thresholds = [float(value) for value in sys.argv[3:]]
    real.install()
    truth = read_mot_boxes(GROUND_TRUTH)
    arms = [("today", today, None)] + [(f"behind, T {t}", behind, t) for t in thresholds]
    for half, (first, last) in HALVES.items():
        for name, bundle, threshold in arms:
            second_person.THRESHOLD[0] = threshold
            runtime = Runtime(bundle, threads=2)
            images = []
            try:
                for frame in FrameSource(VIDEO, FrameRange(first, last, 1)):
                    people = [person for person in runtime.run(frame.image).people if not person.weak]
                    images.append(ImageResult(truth_boxes=truth.get(frame.number, np.zeros((0, 4))),
                                              boxes=np.array([p.box for p in people]).reshape(-1, 4),
                                              scores=np.array([p.score for p in people])))
            finally:
                runtime.close()
            evaluation = evaluate(images)
            detections = sum(len(image.scores) for image in images)
            matched = sum(len(pairs) for pairs in evaluation.matches)
            print(f"{half} {name}: {detections} reported, {matched} of {evaluation.ground_truth} annotated found: "
                  f"precision {matched / max(detections, 1):.3f}, recall {matched / evaluation.ground_truth:.3f}, "
                  f"AP50 {evaluation.ap50:.4f}", flush=True)


if __name__ == "__main__":
    main()
