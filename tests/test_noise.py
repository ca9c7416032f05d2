"""Sensor noise: known noise added to the clean demo render in linear light is measured back, from one image and
from frames; degenerate images measure nothing; the model adds the variance it states, once."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vc.calibration.noise import NoiseModel, estimate_noise_image, estimate_noise_video
from vc.calibration.response import Response
from vc.deploy.frames import FrameRange, FrameSource
from vc.io import read_image

REPO = Path(__file__).resolve().parents[1]
SRGB = Response("srgb")


@pytest.fixture(scope="module")
def background() -> np.ndarray:
    return read_image(REPO / "examples/scenes/demo/background.png")


def _slope(encoded: float) -> float:
    """d(linear)/d(encoded) of sRGB at an encoded value on [0, 1]."""
    step = 1e-4
    return float(np.diff(SRGB.decode(np.array([encoded - step, encoded + step])))[0] / (2 * step))


def _sigma_8bit(model: NoiseModel, encoded: float = 0.5) -> float:
    """The model's noise at an encoded level, in 8-bit levels (what the estimate reports at 0.5)."""
    return float(model.sigma(SRGB.decode(np.array([encoded])))[0]) / _slope(encoded) * 255.0


def _constant(levels_at_mid_grey: float) -> NoiseModel:
    """Constant (read-only) noise that is ``levels_at_mid_grey`` 8-bit levels at encoded 0.5."""
    return NoiseModel(shot=0.0, read=levels_at_mid_grey / 255.0 * _slope(0.5))


def _noisy(background: np.ndarray, model: NoiseModel, seed: int) -> np.ndarray:
    return SRGB.encode(model.apply(SRGB.decode(background), np.random.default_rng(seed)))


#: Signal-dependent noise: shot noise dominates (read noise is 0.1 % of full scale); 4.0 levels at mid-grey.
SHOT = NoiseModel(shot=1e-3, read=1e-3)


@pytest.mark.parametrize("levels", [2.0, 4.0, 8.0])
def test_constant_noise_is_measured_from_one_image(background: np.ndarray, levels: float) -> None:
    estimate = estimate_noise_image(_noisy(background, _constant(levels), seed=1), SRGB)
    assert estimate.method == "flat blocks" and estimate.samples > 100
    assert estimate.sigma_at_mid_grey_8bit == pytest.approx(levels, rel=0.2)


def test_signal_dependent_noise_is_measured_from_one_image(background: np.ndarray) -> None:
    estimate = estimate_noise_image(_noisy(background, SHOT, seed=2), SRGB)
    assert estimate.sigma_at_mid_grey_8bit == pytest.approx(_sigma_8bit(SHOT), rel=0.2)
    # The fit finds the noise growing with the signal in linear light, not a constant.
    assert estimate.model.shot > 0.5 * SHOT.shot


def test_the_clean_render_reads_as_noiseless(background: np.ndarray) -> None:
    """Its fine texture is not noise: below the half level at which the sensor-noise effect switches on."""
    estimate = estimate_noise_image(background, SRGB)
    assert estimate.samples > 0
    assert estimate.sigma_at_mid_grey_8bit < 0.5


def test_a_float_image_reads_as_its_8_bit_values(background: np.ndarray) -> None:
    noisy = _noisy(background, _constant(4.0), seed=3)
    as_float = estimate_noise_image(noisy / 255.0, SRGB)
    assert as_float.sigma_at_mid_grey_8bit == pytest.approx(estimate_noise_image(noisy, SRGB).sigma_at_mid_grey_8bit,
                                                           rel=1e-3)


@pytest.mark.parametrize("model", [_constant(2.0), _constant(8.0), SHOT], ids=["2 levels", "8 levels", "shot"])
def test_noise_is_measured_from_frames(background: np.ndarray, model: NoiseModel) -> None:
    frames = [_noisy(background, model, seed) for seed in range(8)]
    estimate = estimate_noise_video(frames, background, SRGB)
    assert estimate.method == "temporal variance" and estimate.samples > 100_000
    assert estimate.sigma_at_mid_grey_8bit == pytest.approx(_sigma_8bit(model), rel=0.2)
    # Temporal variance has no texture to reject: the whole curve is right, not only mid-grey.
    for level in (0.2, 0.7):
        assert _sigma_8bit(estimate.model, level) == pytest.approx(_sigma_8bit(model, level), rel=0.1)


def test_people_walking_through_the_frames_are_left_out(background: np.ndarray) -> None:
    model = _constant(3.0)
    frames = []
    for seed in range(8):
        frame = _noisy(background, model, seed)
        frame[200:400, 100 + 80 * seed : 160 + 80 * seed] = (200, 40, 40)  # a red coat, one step further each frame
        frames.append(frame)
    estimate = estimate_noise_video(frames, background, SRGB)
    assert estimate.sigma_at_mid_grey_8bit == pytest.approx(3.0, rel=0.2)
    assert estimate.samples < 3 * (background.shape[0] * background.shape[1] - 200 * 60)


@pytest.mark.pets
def test_pets_frames_carry_noise_their_median_background_does_not(pets_data: Path) -> None:
    """A real camera: its frames vary in time by a level or more, its temporal-median background is far cleaner
    (what the sensor-noise effect must not add twice)."""
    background = read_image(pets_data / "background.png")
    frames = [frame.image for frame in FrameSource(pets_data / "vtest.avi", FrameRange(1, 240, 10))]
    in_frames = estimate_noise_video(frames, background, SRGB)
    assert in_frames.samples > 100_000 and in_frames.sigma_at_mid_grey_8bit > 1.0
    assert estimate_noise_image(background, SRGB).sigma_at_mid_grey_8bit < 0.5 * in_frames.sigma_at_mid_grey_8bit


@pytest.mark.parametrize("image", [np.full((120, 160, 3), 128, np.uint8), np.zeros((120, 160, 3), np.uint8),
                                   np.full((120, 160, 3), 255, np.uint8), np.full((4, 4, 3), 90, np.uint8)],
                         ids=["grey", "black", "white", "4x4"])
def test_images_without_measurable_noise_give_a_zero_model(image: np.ndarray) -> None:
    estimate = estimate_noise_image(image, SRGB)
    assert estimate.samples == 0
    assert estimate.model == NoiseModel(0.0, 0.0) and estimate.sigma_at_mid_grey_8bit == 0.0
    saturated = image.copy()
    saturated[::2] = 255
    assert np.isfinite(estimate_noise_video([image, saturated, image], image, SRGB).sigma_at_mid_grey_8bit)


def test_bad_inputs_are_named() -> None:
    image = np.full((64, 64, 3), 0.5)
    image[3, 4, 1] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        estimate_noise_image(image, SRGB)
    frame = np.full((64, 64, 3), 100, np.uint8)
    with pytest.raises(ValueError, match="at least 3 frames"):
        estimate_noise_video([frame, frame], frame, SRGB)
    with pytest.raises(ValueError, match="background"):
        estimate_noise_video([frame] * 3, frame[:32], SRGB)


def test_apply_adds_the_model_variance() -> None:
    model = NoiseModel(shot=2e-3, read=0.01)
    linear = np.full((1000, 1000), 0.3, np.float32)
    noisy = model.apply(linear, np.random.default_rng(0))
    assert noisy.dtype == np.float32 and np.isfinite(noisy).all()
    assert np.var(noisy - linear) == pytest.approx(2e-3 * 0.3 + 0.01**2, rel=0.05)
    assert abs(float(np.mean(noisy - linear))) < 1e-4


def test_apply_does_not_add_the_variance_already_there() -> None:
    model = NoiseModel(shot=2e-3, read=0.01)
    linear = np.full((1000, 1000), 0.3, np.float32)
    total = 2e-3 * 0.3 + 0.01**2
    kept = model.apply(linear, np.random.default_rng(0), keep_variance=np.float32(0.75 * total))
    assert np.var(kept - linear) == pytest.approx(0.25 * total, rel=0.05)
    np.testing.assert_array_equal(model.apply(linear, np.random.default_rng(0), keep_variance=2 * total), linear)


def test_apply_is_deterministic_and_does_not_clip() -> None:
    model = NoiseModel(shot=1e-3, read=0.05)
    linear = np.random.default_rng(5).random((64, 48, 3)).astype(np.float32)
    first = model.apply(linear, np.random.default_rng(7))
    assert first.tobytes() == model.apply(linear, np.random.default_rng(7)).tobytes()
    assert first.tobytes() != model.apply(linear, np.random.default_rng(8)).tobytes()
    assert first.min() < 0.0 and first.max() > 1.0


def test_the_model_survives_its_dict() -> None:
    model = NoiseModel(shot=3e-4, read=2e-3)
    assert NoiseModel(**model.to_dict()) == model
    assert model.variance(np.array([0.5]))[0] == pytest.approx(3e-4 * 0.5 + 2e-3**2)
