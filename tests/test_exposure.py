"""A frame lit beyond the bundle's range brought back to the background's exposure (vc.deploy.exposure): the table
scales light through the camera's response, and only frames within reach beyond the range are corrected."""

from __future__ import annotations

import numpy as np
import pytest

from vc.calibration.response import Response
from vc.deploy.exposure import REACH_STOPS, correction_stops, exposed, exposure_table

SRGB_DECODE = Response("srgb").decode(np.arange(256, dtype=np.uint8)).astype(np.float64)


def test_no_change_is_the_identity_and_the_table_rises():
    assert np.array_equal(exposure_table(SRGB_DECODE, 0.0), np.arange(256))
    for stops in (-4.0, -1.5, 0.7, 3.0):
        table = exposure_table(SRGB_DECODE, stops)
        assert table.dtype == np.uint8 and np.all(np.diff(table.astype(int)) >= 0)


def test_a_stop_up_then_down_returns_the_codes_it_kept():
    codes = np.arange(256, dtype=np.uint8)
    up = exposed(codes[None, :, None].repeat(3, axis=2), SRGB_DECODE, 1.0)
    back = exposed(up, SRGB_DECODE, -1.0)[0, :, 0].astype(int)
    unclipped = SRGB_DECODE * 2 < SRGB_DECODE[-1]
    assert np.abs(back[unclipped] - codes[unclipped]).max() <= 1  # the light, not the codes, was doubled
    assert up[0, -1, 0] == 255 and back[-1] < 255  # clipped light stays clipped: white becomes its grey


def test_the_light_is_scaled_not_the_codes():
    table = exposure_table(SRGB_DECODE, -1.0)
    for code in (60, 120, 200):
        assert SRGB_DECODE[table[code]] == pytest.approx(SRGB_DECODE[code] / 2, rel=0.03)


@pytest.mark.parametrize(("exposure", "expected"), [
    (0.0, None), (1.2, None), (-3.0, None),  # within the range
    (1.8, -1.8), (-3.7, 3.7),  # beyond it, within reach: to the background's exposure
    (1.25 + REACH_STOPS + 0.01, None), (-3.21 - REACH_STOPS - 0.01, None),  # beyond the reach
])
def test_only_frames_within_reach_beyond_the_range_are_corrected(exposure, expected):
    assert correction_stops(exposure, 3.21, 1.25) == expected
