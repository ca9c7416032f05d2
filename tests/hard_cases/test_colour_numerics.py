"""Colour transforms at their edges: 0, 1, above 1, negative, huge: finite; NaN refused; round trips within 1/255."""

from __future__ import annotations

import numpy as np
import pytest
from hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vc.calibration.response import Response

RESPONSES = st.sampled_from(["srgb", "linear", "gamma 1.8", "gamma 2.2", "gamma 2.6"])


@PROPERTY
@given(name=RESPONSES, values=arrays(np.float64, st.integers(1, 64),
                                     elements=st.floats(allow_nan=False, allow_infinity=True)))
def test_decoding_and_encoding_any_number_stays_finite(name, values):
    response = Response(name)
    assert np.isfinite(response.decode(np.clip(values, -1e6, 1e6))).all()  # no light level is infinite
    encoded = response.encode(values)
    assert encoded.dtype == np.uint8
    assert np.array_equal(response.encode_exact(values), np.clip(response.encode_exact(values), 0, 255))


@PROPERTY
@given(name=RESPONSES, levels=arrays(np.uint8, st.integers(1, 256)))
def test_every_8_bit_level_round_trips(name, levels):
    response = Response(name)
    assert np.abs(response.encode(response.decode(levels)).astype(int) - levels).max() <= 1


@pytest.mark.parametrize("name", ["srgb", "linear", "gamma 2.2"])
def test_nan_is_refused_by_name(name):
    with pytest.raises(ValueError, match="NaN"):
        Response(name).encode(np.array([0.5, np.nan]))
    with pytest.raises(ValueError, match="NaN"):
        Response(name).decode(np.array([0.5, np.nan]))
