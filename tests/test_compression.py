"""JPEG compression: the quality and chroma subsampling the demo render was compressed with are found again; an
uncompressed image shows none; the round trip keeps RGB order and honours the subsampling asked for."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vc.calibration.compression import JpegEstimate, blockiness, estimate_jpeg, jpeg_round_trip
from vc.io import read_image

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def background() -> np.ndarray:
    return read_image(REPO / "examples/scenes/demo/background.png")


@pytest.mark.parametrize("subsampled", [True, False], ids=["4:2:0", "4:4:4"])
@pytest.mark.parametrize("quality", [30, 50, 70, 90])
def test_quality_and_subsampling_are_found(background: np.ndarray, quality: int, subsampled: bool) -> None:
    estimate = estimate_jpeg(jpeg_round_trip(background, quality, subsampled))
    assert estimate.quality is not None and abs(estimate.quality - quality) <= 10, estimate.evidence
    assert estimate.chroma_subsampling is subsampled, estimate.evidence


def test_an_uncompressed_render_shows_no_compression(background: np.ndarray) -> None:
    estimate = estimate_jpeg(background)
    assert estimate.quality is None and estimate.chroma_subsampling is False
    assert estimate.evidence["ghost_dip_ratio"] > 0.8  # no dip at all, not a near miss


def test_a_crop_off_the_block_grid_hides_the_compression(background: np.ndarray) -> None:
    assert estimate_jpeg(jpeg_round_trip(background, 50, True)[3:, 5:]).quality is None


@pytest.mark.parametrize("image", [np.full((64, 64, 3), 77, np.uint8), np.zeros((10, 12, 3), np.uint8)],
                         ids=["flat", "smaller than a block"])
def test_images_with_nothing_to_see_show_no_compression(image: np.ndarray) -> None:
    assert estimate_jpeg(image) == JpegEstimate(None, False, estimate_jpeg(image).evidence)
    assert blockiness(image) == pytest.approx(1.0, abs=0.5)


def test_blockiness_grows_as_quality_falls(background: np.ndarray) -> None:
    uncompressed = blockiness(background)
    assert uncompressed == pytest.approx(1.0, abs=0.1)
    measured = [blockiness(jpeg_round_trip(background, quality, True)) for quality in (90, 50, 20)]
    assert uncompressed < measured[0] < measured[1] < measured[2]
    assert measured[1] > 1.3


def test_round_trip_keeps_rgb_order_and_the_subsampling_asked_for() -> None:
    image = np.zeros((64, 64, 3), np.uint8)
    image[:, :, 0] = 220  # red everywhere ...
    image[:, 1::2, 2] = 200  # ... with single-pixel blue stripes: chroma detail that 4:2:0 cannot keep
    full = jpeg_round_trip(image, 95, False)
    subsampled = jpeg_round_trip(image, 95, True)
    assert full.dtype == np.uint8 and full.shape == image.shape
    assert full[..., 0].mean() > 180 and full[:, 0::2, 2].mean() < 40
    full_error = np.abs(full.astype(int) - image).mean()
    assert full_error < 0.5 * np.abs(subsampled.astype(int) - image).mean()


def test_inputs_other_than_rgb_uint8_are_refused() -> None:
    with pytest.raises(ValueError, match="RGB uint8"):
        estimate_jpeg(np.zeros((32, 32, 3), np.float32))
    with pytest.raises(ValueError, match="RGB uint8"):
        jpeg_round_trip(np.zeros((32, 32), np.uint8), 50, False)


@pytest.mark.parametrize("quality", [25, 60])
def test_the_equivalent_quality_matches_the_visible_blocking(background: np.ndarray, quality: int) -> None:
    from vc.calibration.compression import equivalent_quality

    blocked = blockiness(jpeg_round_trip(background, quality, True))
    assert equivalent_quality(background, blocked) == quality
    assert equivalent_quality(background, 1.0) is None or equivalent_quality(background, 1.0) >= 95


def test_video_frames_without_a_ghost_are_matched_by_their_blocking(background: np.ndarray) -> None:
    """A video codec's frames are no JPEG fixed point (here: noisy frames blocked at quality 40, then a little more
    noise on top, as the next frame's residual adds): the compression is matched by its visible blocking, on the
    background with the frames' noise in."""
    from vc.calibration.noise import NoiseModel
    from vc.calibration.response import Response
    from vc.render.camera_measurements import video_compression

    rng, response = np.random.default_rng(0), Response("srgb")
    crop = background[:256, :384]
    noise = NoiseModel(shot=2e-4, read=0.0)

    def frame() -> np.ndarray:
        blocked = jpeg_round_trip(response.encode(noise.apply(response.decode(crop), rng)), 40, True)
        return np.clip(blocked + rng.normal(0, 1.2, blocked.shape), 0, 255).astype(np.uint8)

    estimate = video_compression([frame() for _ in range(6)], crop, noise, response)
    assert estimate.evidence["method"] == "blockiness matched on the background"
    assert estimate.chroma_subsampling and 25 <= estimate.quality <= 55
    assert video_compression([crop] * 6, crop, NoiseModel(0.0, 0.0), response).quality is None
