"""The head-map bundles as shipped, with a region adding a person read from the heads only where their head's peak
reaches THRESHOLD (as shipped: the centre threshold, 0.3) (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure.py THRESHOLD CAMERA BUNDLE --seed S

0058 found that step 5 costs PETS09's choosing half 0.008 AP50 tracked against the same networks read without it,
and gains TUD-Stadtmitte's each frame. Is a surer head what keeps PETS09's loss away and TUD-Stadtmitte's gain? The
runtime's union (``vc.deploy.decode.with_heads_added``) is given the heads' people at or above THRESHOLD only; the
rest is as shipped. Measured as results-as-shipped measures; writes ``results/THRESHOLD/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import vc.deploy.runtime as runtime

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)

_WITH_HEADS_ADDED = runtime.with_heads_added


def heads_added_above(threshold: float):
    def with_heads_added(people: list, max_people: int) -> list:
        return _WITH_HEADS_ADDED([person for person in people if not person.head_found or person.score >= threshold],
                                 max_people)
    return with_heads_added


if __name__ == "__main__":
    threshold = sys.argv.pop(1)
    runtime.with_heads_added = heads_added_above(float(threshold))
    shipped_measure.RESULTS = Path(__file__).parent / "results" / threshold
    shipped_measure.main()
