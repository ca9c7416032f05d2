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

from functools import partial

import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring

from vc.deploy.tracking import Tracker, TrackingConfig

ARMS = {"as shipped": TrackingConfig(),
        "a walk 1.5 standard errors clear": TrackingConfig(min_significance=1.5),
        "a walk 1 standard error clear": TrackingConfig(min_significance=1.0)}


if __name__ == "__main__":
    clarity.run({name: partial(Tracker, config) for name, config in ARMS.items()})
