"""Optical blur: known Gaussian blur on the demo render and on ideal edges is measured back; blurring keeps shapes
and dtypes; blur that is already there is not added twice."""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from vc.calibration.sharpness import BlurEstimate, added_blur, estimate_blur_sigma, gaussian_blur
from vc.io import read_image

REPO = Path(__file__).resolve().parents[1]
#: The blur of a box-filtered pixel (its footprint's standard deviation).
PIXEL_BLUR = 1.0 / math.sqrt(12.0)


@pytest.fixture(scope="module")
def background() -> np.ndarray:
    return read_image(REPO / "examples/scenes/demo/background.png")


def _blurred(image: np.ndarray, sigma: float) -> np.ndarray:
    return np.clip(np.round(gaussian_blur(image.astype(np.float32), sigma)), 0, 255).astype(np.uint8)


def _ideal_edges(sigma: float, tiles: int = 8, tile: int = 50, supersampling: int = 8) -> np.ndarray:
    """Straight edges at random angles and subpixel offsets, each pixel the mean over its area (as a box-filtered
    render is), then blurred by ``sigma``: grey RGB uint8."""
    rng = np.random.default_rng(0)
    fine = (np.arange(tile * supersampling) + 0.5) / supersampling - tile / 2
    ys, xs = np.meshgrid(fine, fine, indexing="ij")
    rows = []
    for _ in range(tiles):
        row = []
        for _ in range(tiles):
            angle, offset = rng.uniform(0.0, np.pi), rng.uniform(-3.0, 3.0)
            inside = (np.cos(angle) * xs + np.sin(angle) * ys > offset).astype(np.float32)
            row.append(60.0 + 120.0 * inside.reshape(tile, supersampling, tile, supersampling).mean(axis=(1, 3)))
        rows.append(np.concatenate(row, axis=1))
    image = gaussian_blur(np.concatenate(rows, axis=0), sigma)
    return np.repeat(np.round(image)[..., None], 3, axis=2).astype(np.uint8)


def test_the_render_is_sharp(background: np.ndarray) -> None:
    estimate = estimate_blur_sigma(background)
    assert estimate.edges > 1000
    assert 0.0 < estimate.sigma_px < 1.0


@pytest.mark.parametrize("sigma", [1.0, 1.5, 2.5])
def test_known_blur_is_measured_on_the_render(background: np.ndarray, sigma: float) -> None:
    own = estimate_blur_sigma(background).sigma_px
    estimate = estimate_blur_sigma(_blurred(background, sigma))
    assert estimate.sigma_px == pytest.approx(math.hypot(sigma, own), rel=0.2)


@pytest.mark.parametrize("sigma", [0.5, 1.0, 1.5, 2.5])
def test_blur_is_measured_on_ideal_edges(sigma: float) -> None:
    """Absolute, not only relative to the render: the blur plus the box-filtered pixel's own, within 0.08 px."""
    estimate = estimate_blur_sigma(_ideal_edges(sigma))
    assert estimate.edges > 1000
    assert estimate.sigma_px == pytest.approx(math.hypot(sigma, PIXEL_BLUR), abs=0.08)


def test_unblurred_ideal_edges_read_below_half_a_pixel() -> None:
    """Below ~0.4 px the pixel grid limits the method: the box-filtered pixel's 0.29 px reads a little high."""
    assert PIXEL_BLUR < estimate_blur_sigma(_ideal_edges(0.0)).sigma_px < 0.5


def test_noise_does_not_read_as_sharpness(background: np.ndarray) -> None:
    noisy = np.clip(background + np.random.default_rng(0).normal(0.0, 4.0, background.shape), 0, 255)
    own = estimate_blur_sigma(background).sigma_px
    assert estimate_blur_sigma(noisy.astype(np.uint8)).sigma_px == pytest.approx(own, rel=0.2)


@pytest.mark.parametrize("image", [np.full((120, 160, 3), 90, np.uint8), np.zeros((8, 8, 3), np.uint8)],
                         ids=["flat", "tiny"])
def test_no_edges_no_blur(image: np.ndarray) -> None:
    assert estimate_blur_sigma(image) == BlurEstimate(0.0, 0)
    assert BlurEstimate(0.0, 0).to_dict() == {"sigma_px": 0.0, "edges": 0}


def test_gaussian_blur_keeps_shape_dtype_and_the_mean() -> None:
    rng = np.random.default_rng(1)
    for shape in [(40, 50), (40, 50, 1), (40, 50, 3), (40, 50, 600)]:
        image = rng.random(shape).astype(np.float32)
        blurred = gaussian_blur(image, 1.5)
        assert blurred.shape == image.shape and blurred.dtype == image.dtype
        assert blurred.std() < 0.5 * image.std()
        assert blurred.mean() == pytest.approx(image.mean(), abs=5e-3)
    many = rng.random((40, 50, 600)).astype(np.float32)
    np.testing.assert_allclose(gaussian_blur(many, 1.5)[..., 555], gaussian_blur(many[..., 555], 1.5), atol=1e-6)


def test_gaussian_blur_of_zero_is_a_copy() -> None:
    image = np.random.default_rng(2).random((20, 30, 3)).astype(np.float32)
    copy = gaussian_blur(image, 0.0)
    assert copy is not image
    np.testing.assert_array_equal(copy, image)
    with pytest.raises(ValueError, match="sigma"):
        gaussian_blur(image, -1.0)


def test_a_gaussian_of_the_added_blur_reaches_the_target() -> None:
    assert added_blur(5.0, 3.0) == pytest.approx(4.0)
    assert added_blur(1.0, 2.0) == 0.0
    impulse = np.zeros((101, 101), np.float32)
    impulse[50, 50] = 1.0
    twice = gaussian_blur(gaussian_blur(impulse, 1.2), added_blur(2.0, 1.2))
    np.testing.assert_allclose(twice, cv2.GaussianBlur(impulse, (0, 0), 2.0, borderType=cv2.BORDER_REFLECT),
                               atol=2e-4)
