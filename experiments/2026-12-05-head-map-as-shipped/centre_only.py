"""A head-map bundle read without its head map: each region's maps cut to the fine centre map's layout, so the
decoder's step 5 does not run (frozen experiment, issue 57 item 2). What the retraining with the head map changes
in the centre map's people, apart from the people read from the heads.

    PYTHONPATH=../../src python centre_only.py CAMERA BUNDLE --seed S

Measured as ``measure.py`` measures; writes ``results/centre_only/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

from pathlib import Path

from measure import shipped_measure

import vc.deploy.runtime as runtime
from vc.deploy.heatmaps import FINE_CHANNELS

_HEATMAPS = runtime.RegionRunner.heatmaps

if __name__ == "__main__":
    runtime.RegionRunner.heatmaps = lambda self, frame: _HEATMAPS(self, frame)[:FINE_CHANNELS]
    shipped_measure.RESULTS = Path(__file__).parent / "results" / "centre_only"
    shipped_measure.main()
