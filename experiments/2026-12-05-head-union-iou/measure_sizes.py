"""The head-map bundles as shipped, with the heads' people's boxes as tall as the camera's expected height at their
centre (``expected``), or as the size map's height kept within a factor of it (``within-F``) (frozen experiment,
issue 57 item 2).

    PYTHONPATH=../../src python measure_sizes.py ARM CAMERA BUNDLE --seed S

``measure_heights.py`` gave the heads' people the centre reading's heights (head and ankle keypoints, else the
expected height): PETS09's choosing half gained and TUD-Stadtmitte's lost. These arms leave the keypoints out: a
person behind another has a neighbour's ankles below them. The size map still places each head's person's centre;
only the box's height changes. Decoded by the numpy decoder. Writes ``results/ARM/CAMERA/seedS_HALF.json``.
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
_READ, _CENTRES_FROM_HEADS = decode._read, decode._centres_from_heads
_expected = threading.local()  # .heights: the expected heights (h, w) of the region this thread reads


def read_remembering_expected(heatmaps, config, expected_height_px, *args, **kwargs):
    _expected.heights = expected_height_px
    return _READ(heatmaps, config, expected_height_px, *args, **kwargs)


def sized_by(factor: float | None):
    """``_centres_from_heads`` giving the expected heights (cells) at the centres, or the size map's within
    ``factor`` of them."""
    def centres_from_heads(heatmaps: np.ndarray, heads_cells: np.ndarray, stride: int):
        centres, sizes = _CENTRES_FROM_HEADS(heatmaps, heads_cells, stride)
        expected_px = _expected.heights
        if expected_px is None:
            return centres, sizes
        height, width = expected_px.shape
        rows = np.clip(np.round(centres[:, 1]).astype(int), 0, height - 1)
        columns = np.clip(np.round(centres[:, 0]).astype(int), 0, width - 1)
        expected = expected_px[rows, columns].astype(np.float64) / stride
        return centres, expected if factor is None else np.clip(sizes, expected / factor, expected * factor)
    return centres_from_heads


if __name__ == "__main__":
    arm = sys.argv.pop(1)
    decode.HEAD_HEIGHT_AGREEMENT = 0.5  # as 0058 shipped it: no height agrees, the size map's always
    decode._read = read_remembering_expected
    decode._centres_from_heads = sized_by(None if arm == "expected" else float(arm.removeprefix("within-")))
    native.decode_readings = decode.decode_readings
    shipped_measure.RESULTS = Path(__file__).parent / "results" / arm
    shipped_measure.main()
