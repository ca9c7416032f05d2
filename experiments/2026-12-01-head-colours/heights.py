"""How many of the people a bundle reports (not weak, ordered by its facing model) are shorter than the head reader's
gate, each half: where none is, the head's colours change nothing (vc.deploy.facing.front_logits) and the arm is the
control (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-head-colours/heights.py BUNDLE tud|pets \
        >> experiments/2026-12-01-head-colours/results/heights.jsonl
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.facing import HEAD_READ_BELOW_PX
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", ((1, 90, 1), (91, 179, 1)))}


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    video, halves = DATA[camera]
    with Runtime(bundle, threads=2) as runtime:
        for first, last, step in halves:
            heights = [float(p.box[3] - p.box[1]) for frame in FrameSource(Path(video), FrameRange(first, last, step))
                       for p in runtime.run(frame.image).people if not p.weak and p.pair_handedness is not None]
            print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": [first, last, step],
                              "people": len(heights), "under_gate": int(np.sum(np.array(heights) < HEAD_READ_BELOW_PX)),
                              "gate_px": HEAD_READ_BELOW_PX,
                              "height_percentiles_5_50_95": [round(float(v), 1)
                                                             for v in np.percentile(heights, [5, 50, 95])]}),
                  flush=True)


if __name__ == "__main__":
    main()
