"""Real-frame figures of a bundle retrained on seed 0's renders with another training seed (frozen experiment,
issue 57), measured exactly as ``../2026-12-05-results-as-shipped/measure.py`` measures the scenes as they ship.

    PYTHONPATH=../../src python measure.py CAMERA BUNDLE --seed T      # CAMERA: pets or tud; T: the training seed

Writes ``results/CAMERA/seedT_HALF.json``; a finished file is not run again.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)

if __name__ == "__main__":
    shipped_measure.RESULTS = Path(__file__).parent / "results"
    shipped_measure.main()
