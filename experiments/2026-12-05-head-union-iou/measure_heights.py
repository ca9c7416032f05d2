"""The head-map bundles as shipped, with the heads' people's boxes as tall as the centre reading's would be (their
head and ankle keypoints, else the camera's expected height at their centre) instead of the size map's height
(frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_heights.py CAMERA BUNDLE --seed S

On TUD-Stadtmitte's choosing half the people in groups that the head-map bundles miss mostly have a head reading
whose head is theirs, and its box is too tall (1.2-1.3x) and too wide (1.4-1.8x). Over every person, the heads'
boxes' heights spread wider than the centre reading's (quartiles 0.93-1.15 of the truth's against 0.95-1.04). The
size map still places each head's person's centre; only the box's height changes. Decoded by the numpy decoder
(the C decoder reads the same, tests/hard_cases/test_native_decode.py). Writes
``results/heights/CAMERA/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

import vc.deploy.decode as decode
import vc.deploy.native as native

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)
_CENTRES_FROM_HEADS = decode._centres_from_heads


def centres_from_heads_unsized(heatmaps: np.ndarray, heads_cells: np.ndarray, stride: int
                               ) -> tuple[np.ndarray, np.ndarray]:
    centres, _ = _CENTRES_FROM_HEADS(heatmaps, heads_cells, stride)
    return centres, np.full(len(centres), np.nan)


if __name__ == "__main__":
    decode._centres_from_heads = centres_from_heads_unsized
    native.decode_readings = decode.decode_readings
    shipped_measure.RESULTS = Path(__file__).parent / "results" / "heights"
    shipped_measure.main()
