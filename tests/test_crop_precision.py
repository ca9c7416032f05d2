"""The facing and keypoint models at int8 where it holds (vc.model.crop_precision)."""

from __future__ import annotations

import numpy as np
import pytest

from vc.model.crop_precision import CropPrecision, choose, side_by_side


def test_crops_pasted_side_by_side_are_cut_back_at_their_own_places():
    crops = np.random.default_rng(0).integers(0, 255, (3, 8, 4, 3)).astype(np.uint8)
    frame, rois = side_by_side(crops)
    assert frame.shape == (1, 8, 12, 3)
    for crop, (x0, y0, x1, y1) in zip(crops, rois, strict=True):
        np.testing.assert_array_equal(frame[0, int(y0):int(y1), int(x0):int(x1)], crop)


@pytest.mark.parametrize(("fp32", "int8", "kept"), [
    (0.90, 0.895, "int8"),  # within the tolerance
    (0.90, 0.85, "fp32"),  # beyond it
    (None, 0.5, "int8"),  # nothing held out to measure on
])
def test_int8_ships_only_where_it_reads_the_held_out_crops_within_the_tolerance(monkeypatch, fp32, int8, kept):
    import vc.model.crop_precision as precision

    monkeypatch.setattr(precision, "to_int8", lambda model, calibration: b"int8")
    chosen = choose(b"fp32", np.zeros((4, 8, 4, 3), np.uint8), {b"fp32": fp32, b"int8": int8}.get, tolerance=0.01)
    assert chosen == CropPrecision(kept, kept.encode(), {"fp32": fp32, "int8": int8})


def test_without_crops_to_calibrate_on_the_graph_ships_fp32():
    chosen = choose(b"fp32", np.zeros((0, 8, 4, 3), np.uint8), lambda model: 0.9, tolerance=0.01)
    assert chosen == CropPrecision("fp32", b"fp32", {"fp32": 0.9})
