"""A bundle compiled as the scene ships with the head map, on both halves, as ``../2026-12-05-results-as-shipped``
measures the shipped bundles (frozen experiment, issue 57 item 2): its ``measure.py``, writing here.

    PYTHONPATH=../../src python measure.py CAMERA BUNDLE --seed S      # CAMERA: pets or tud

Writes ``results/CAMERA/seedS_HALF.json``; a finished file is not run again. The control is results-as-shipped's
``results/CAMERA/seedS_HALF.json``.
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
