"""The head-map bundles as main reads them (0060), with the heads' people as wide as a fixed share of their height
(frozen experiment, issue 57 item 2): a proxy for a learned width, before training one.

    PYTHONPATH=../../src python measure_aspect.py ARM CAMERA BUNDLE --seed S      # ARM: aspect or split-aspect

``head-union-iou/where_lost.py``: a person in a group missed although their head is read comes out of the head
reading 1.8x as wide as they are (medians), and ``split`` (a merged centre box replaced by the heads' people) lost
because the heads' boxes were too big to match. Here every strong person of the head reading is ASPECT of their
box's height wide, centred on their centre; ``split-aspect`` also splits merged centre boxes as ``split`` does.
ASPECT is the box :data:`vc.deploy.decode.PERSON_AREA` describes (0.37 heights), set before measuring. Decoded by
the C decoder; only its head reading's boxes change. Writes ``results/ARM/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

import vc.deploy.native as native
import vc.deploy.runtime as runtime

HERE = Path(__file__).parent
ASPECT = 0.37
_DECODE_READINGS = native.decode_readings


def _module(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def with_fixed_widths(*args, **kwargs) -> list:
    people = _DECODE_READINGS(*args, **kwargs)
    fixed = []
    for person in people:
        if person.head_found:
            box = np.asarray(person.box, float).copy()
            half = ASPECT * (box[3] - box[1]) / 2
            box[0], box[2] = person.centre[0] - half, person.centre[0] + half
            person = replace(person, box=box)
        fixed.append(person)
    return fixed


if __name__ == "__main__":
    arm = sys.argv.pop(1)
    assert arm in ("aspect", "split-aspect"), arm
    shipped = _module("shipped_measure", HERE.parent / "2026-12-05-results-as-shipped" / "measure.py")
    native.decode_readings = with_fixed_widths
    if arm == "split-aspect":
        split = _module("measure_split", HERE.parent / "2026-12-05-head-union-iou" / "measure_split.py")
        runtime.with_heads_added = split.with_merged_boxes_split
    shipped.RESULTS = HERE / "results" / arm
    shipped.main()
