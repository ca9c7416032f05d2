"""Real-frame figures of this experiment's bundles (frozen experiment, issue 57), measured exactly as
``../2026-12-05-results-as-shipped/measure.py`` measures the scenes as they ship: a bundle retrained on seed 0's
renders with another training seed T, or (``--arm mixed``) a compile of PETS09's scene in 0053's control clothing.

    PYTHONPATH=../../src python measure.py CAMERA BUNDLE --seed T [--arm mixed]      # CAMERA: pets or tud

Writes ``results/CAMERA/seedT_HALF.json`` (``results/mixed/CAMERA/...`` with ``--arm mixed``); a finished file is not
run again.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)

if __name__ == "__main__":
    arm_parser = argparse.ArgumentParser(add_help=False)
    arm_parser.add_argument("--arm", choices=["mixed"])
    arm, rest = arm_parser.parse_known_args()
    shipped_measure.RESULTS = Path(__file__).parent / "results" / (arm.arm or "")
    sys.argv = [sys.argv[0], *rest]
    shipped_measure.main()
