"""Camera responses: 8-bit values survive decode -> encode, and the curves are the standard ones."""

from __future__ import annotations

import colour
import numpy as np
import pytest

from vc.calibration.response import Response

LEVELS = np.arange(256, dtype=np.uint8)


@pytest.mark.parametrize("name", ["srgb", "linear"])
def test_every_8_bit_value_round_trips_exactly(name: str) -> None:
    response = Response(name)
    np.testing.assert_array_equal(response.encode(response.decode(LEVELS)), LEVELS)


def test_gamma_round_trips_within_one_level() -> None:
    response = Response("gamma 2.2")
    assert np.abs(response.encode(response.decode(LEVELS)).astype(int) - LEVELS).max() <= 1
    assert response.decode(np.array([128], np.uint8))[0] == pytest.approx((128 / 255) ** 2.2, rel=1e-5)


def test_srgb_matches_colour_science_and_clips() -> None:
    linear = np.linspace(0.0, 1.0, 1001)
    expected = np.round(colour.cctf_encoding(linear, function="sRGB") * 255)
    assert np.abs(Response("srgb").encode(linear).astype(int) - expected).max() <= 1
    np.testing.assert_array_equal(Response("srgb").encode(np.array([-1.0, 2.0, np.inf])), [0, 255, 255])


def test_the_table_stays_within_one_level_of_the_exact_curve() -> None:
    linear = np.random.default_rng(0).random(100_000).astype(np.float32)
    for name in ("srgb", "gamma 2.2", "linear"):
        response = Response(name)
        assert np.abs(response.encode(linear).astype(int) - response.encode_exact(linear)).max() <= 1


@pytest.mark.parametrize("name", ["srgb", "linear", "gamma 2.2"])
def test_values_outside_the_range_stay_finite_and_nan_is_refused(name: str) -> None:
    response = Response(name)
    values = np.array([0.0, 1.0, 1.7, -0.3, np.inf, -np.inf])
    np.testing.assert_array_equal(response.encode(values), [0, 255, 255, 0, 255, 0])
    np.testing.assert_array_equal(response.encode_exact(values), [0, 255, 255, 0, 255, 0])
    decoded = response.decode(values[:4])
    assert np.isfinite(decoded).all() and decoded[0] == 0.0 and decoded[1] == pytest.approx(1.0)
    for action in (response.encode, response.encode_exact, response.decode):
        with pytest.raises(ValueError, match="NaN"):
            action(np.array([0.5, np.nan]))


@pytest.mark.parametrize("name", ["srgb", "gamma 2.2"])
def test_float_round_trips_stay_within_one_8_bit_step(name: str) -> None:
    response = Response(name)
    encoded = np.linspace(0.0, 1.0, 4097)
    np.testing.assert_allclose(response.encode_exact(response.decode(encoded)) / 255.0, encoded, atol=1 / 255)
