"""The head-map bundles as shipped, with a centre-reading person whose box holds two or more heads' people replaced by
them (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_split.py CAMERA BUNDLE --seed S

On TUD-Stadtmitte's choosing half, a group's people often come out of the centre reading as one box over two or
three of them, and each of their heads as a person of the head reading that the union drops (IoU >= 0.5 with that
box). Here, before the union, a strong centre-reading person is dropped where the head points (box top middle) of
two or more strong heads' people lie in the top of its box (within its sides, from TOP_ABOVE above its top to
TOP_BELOW of its height below it); those heads' people are then added as the union adds any. The rest is as
shipped. Writes ``results/split/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

import vc.deploy.runtime as runtime

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)

_WITH_HEADS_ADDED = runtime.with_heads_added
TOP_ABOVE, TOP_BELOW = 0.1, 0.25


def heads_in_top(box: np.ndarray, heads: np.ndarray) -> int:
    """How many head points (N, 2) lie in the top of ``box`` (x0, y0, x1, y1)."""
    height = box[3] - box[1]
    return int(((heads[:, 0] >= box[0]) & (heads[:, 0] <= box[2]) & (heads[:, 1] >= box[1] - TOP_ABOVE * height)
                & (heads[:, 1] <= box[1] + TOP_BELOW * height)).sum())


def with_merged_boxes_split(people: list, max_people: int) -> list:
    heads = np.array([[(p.box[0] + p.box[2]) / 2, p.box[1]] for p in people if p.head_found and not p.weak]
                     ).reshape(-1, 2)
    kept = [p for p in people if p.head_found or p.weak or heads_in_top(np.asarray(p.box, float), heads) < 2]
    return _WITH_HEADS_ADDED(kept, max_people)


if __name__ == "__main__":
    runtime.with_heads_added = with_merged_boxes_split
    shipped_measure.RESULTS = Path(__file__).parent / "results" / "split"
    shipped_measure.main()
