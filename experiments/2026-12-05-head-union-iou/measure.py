"""The head-map bundles as shipped, with a region adding a person read from the heads where their box overlaps every
strong person of the centre reading by less than IOU (as shipped: 0.5) (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure.py IOU CAMERA BUNDLE --seed S

On TUD-Stadtmitte's choosing half most people in groups that the head-map bundles miss have a head reading whose
head is theirs, and a third of those are dropped by the union: their box overlaps a centre-reading box (often one
drawn over two people) by 0.5 or more. One head, one person (``one_head_each``) still drops a head's person whose
head is a kept person's. ``vc.deploy.decode.HEAD_UNION_IOU`` is set to IOU; the rest is as shipped. Measured as
results-as-shipped measures; writes ``results/IOU/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import vc.deploy.decode as decode

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)


if __name__ == "__main__":
    iou = sys.argv.pop(1)
    decode.HEAD_UNION_IOU = float(iou)
    shipped_measure.RESULTS = Path(__file__).parent / "results" / iou
    shipped_measure.main()
