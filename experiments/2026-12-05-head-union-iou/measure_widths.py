"""The head-map bundles as shipped, with the heads' people's boxes as wide as their confident keypoints span (plus
the margin, at least the narrowest box), not their mask cells too (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_widths.py CAMERA BUNDLE --seed S

``where_lost.py``: the people in groups whose head reading's box misses them are read 1.8x as wide as they are
(medians); a person's mask cells are those whose votes point nearest their centre, and in a group the votes of the
person in front reach behind. The head reading's keypoints are shared out among its people, so each keeps their
own. Only the head reading's boxes change. Decoded by the numpy decoder (the C decoder reads the same,
tests/hard_cases/test_native_decode.py). Writes ``results/widths/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
import threading
from pathlib import Path

import numpy as np

import vc.deploy.decode as decode
import vc.deploy.native as native

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)
_READ, _BOXES = decode._read, decode._boxes
_reading = threading.local()  # .heads: whether this thread reads the heads (the regions run in threads)


def read_flagging_heads(*args, from_heads: bool, **kwargs):
    _reading.heads = from_heads
    try:
        return _READ(*args, from_heads=from_heads, **kwargs)
    finally:
        _reading.heads = False


def boxes_of_keypoints(centres, heights_px, keypoints, owned, mask_columns, config, prior=decode.UPRIGHT_PRIOR):
    if getattr(_reading, "heads", False):
        owned = np.zeros_like(owned)
    return _BOXES(centres, heights_px, keypoints, owned, mask_columns, config, prior)


if __name__ == "__main__":
    decode.HEAD_HEIGHT_AGREEMENT = 0.5  # as 0058 shipped it: no height agrees, the size map's always
    decode._read, decode._boxes = read_flagging_heads, boxes_of_keypoints
    native.decode_readings = decode.decode_readings
    shipped_measure.RESULTS = Path(__file__).parent / "results" / "widths"
    shipped_measure.main()
