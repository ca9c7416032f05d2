"""Now that a sure vote overrules a clear walk (decision 0049), should a less clear walk decide? Pose agreement with
YOLO11n-pose @1280 tracked, both halves (frozen, issue 57).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-walk-clarity \
        python experiments/2026-12-02-a-looser-walk/looser.py BUNDLE SEED CAMERA >> results/arms.jsonl

Who-is-swapped found the track's vote wrong for a third of PETS09's small people it orders, against a tenth of those
the walk orders, and for a quarter of TUD-Stadtmitte's choosing half's. Each arm is the shipped tracker (main at
1e56ccc) with ``min_significance`` 1.0 or 1.5 standard errors (shipped: 2). Same bundles, frame loop and scoring as
walk-clarity (``clarity.half``).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import arms as voted  # experiments/2026-12-02-small-people-voted/arms.py: data and halves
import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring

from vc.deploy.tracking import TrackingConfig

ARMS = {"as shipped": TrackingConfig(),
        "a walk 1.5 standard errors clear": TrackingConfig(min_significance=1.5),
        "a walk 1 standard error clear": TrackingConfig(min_significance=1.0)}


def main() -> None:
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    clarity.ARMS = ARMS
    for name, (first, last, step) in zip(voted.HALVES, voted.DATA[camera][3], strict=True):
        readings = clarity.half(bundle, camera, first, last, step)
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "frames": [first, last, step], **readings}), flush=True)


if __name__ == "__main__":
    main()
