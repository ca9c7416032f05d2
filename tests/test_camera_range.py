"""The camera range: every training window varied over exposure, white balance, night IR, gain noise, blur and
compression as a camera would show it, each draw a pure function of its generator (vc.model.camera_range)."""

from __future__ import annotations

import numpy as np
import pytest

from vc.calibration.noise import NoiseModel
from vc.calibration.response import Response
from vc.errors import InputError
from vc.model.camera_range import (
    CameraLife,
    CameraRange,
    Condition,
    camera_life_of,
    disc_kernel,
    line_kernel,
    plan_lines,
    white_balance_gains,
)
from vc.stages.config import PRESETS, with_overrides

SRGB = Response("srgb")
#: PETS09's frames' noise as the render plan measured it.
PETS_NOISE = NoiseModel(shot=2.3e-4, read=0.0)


def _window(seed: int = 0, size: int = 64) -> np.ndarray:
    """A smooth, coloured window (a gradient with a mid-grey patch), codes well inside 0-255."""
    ys, xs = np.mgrid[0:size, 0:size] / size
    image = np.stack([60 + 120 * xs, 80 + 100 * ys, 70 + 60 * (1 - xs)], axis=-1)
    image[size // 4:size // 2, size // 4:size // 2] = 118
    return np.round(image + np.random.default_rng(seed).normal(0, 1, image.shape)).clip(0, 255).astype(np.uint8)


def _life(**fields) -> CameraLife:
    return CameraLife(CameraRange(**fields), SRGB, PETS_NOISE, region_scale=1.0)


def test_the_share_not_varied_is_returned_untouched():
    life = _life(varied=0.0)
    window = _window()
    rng = np.random.default_rng(3)
    assert all(life.apply(window, rng) is window for _ in range(20))


def test_every_draw_is_a_pure_function_of_its_generator():
    life, window = _life(), _window()
    first = [life.apply(window, np.random.default_rng([7, k])) for k in range(30)]
    second = [_life().apply(window, np.random.default_rng([7, k])) for k in range(30)]
    assert all(np.array_equal(a, b) for a, b in zip(first, second, strict=True))
    assert sum(not np.array_equal(a, window) for a in first) >= 15  # three in four are varied


@pytest.mark.parametrize("stops", [-2.0, -1.0, 1.0])
def test_exposure_scales_the_light_not_the_codes(stops):
    """Two stops less light is a quarter of the linear light through the camera response (codes fall by less than
    a quarter); no gain recovers it and noise is off, so the ratio is exact to the 8-bit rounding."""
    life = CameraLife(CameraRange(), SRGB, NoiseModel(0.0, 0.0), 1.0)
    window = _window()
    varied = life.render(window, Condition(stops=stops), np.random.default_rng(0))
    before, after = SRGB.decode(window), SRGB.decode(varied)
    unclipped = (before * 2.0 ** stops < 0.95) & (before > 0.05)
    ratio = np.median(after[unclipped] / before[unclipped])
    assert ratio == pytest.approx(2.0 ** stops, rel=0.03)


def test_a_dark_frame_brought_back_by_gain_is_as_bright_and_noisier():
    life, window = _life(), _window(size=128)
    varied = life.render(window, Condition(stops=-2.0, recovered_stops=2.0), np.random.default_rng(0))
    assert abs(float(varied.mean()) - float(window.mean())) < 2.0
    patch = np.s_[40:56, 40:56]  # inside the flat mid-grey patch
    assert varied[patch].astype(float).std() > 2.0 * window[patch].astype(float).std()


def test_white_balance_gains_follow_the_planckian_locus():
    assert np.allclose(white_balance_gains(0.0), 1.0)
    warm, cool = white_balance_gains(45.0), white_balance_gains(-45.0)
    assert warm[1] == cool[1] == 1.0
    assert warm[0] > 1.15 and warm[2] < 0.85  # R x1.25, B x0.8 is about 45 mired warmer
    assert cool[0] < 0.9 and cool[2] > 1.15


def test_night_ir_makes_the_three_channels_one():
    life, window = _life(), _window()
    varied = life.render(window, Condition(ir_mix=(0.5, 0.3, 0.2)), np.random.default_rng(0))
    assert np.array_equal(varied[..., 0], varied[..., 1]) and np.array_equal(varied[..., 1], varied[..., 2])
    assert _life(night_ir=0.0, varied=1.0).range.night_ir == 0.0
    rng = np.random.default_rng(0)
    assert not any(_life(night_ir=0.0, varied=1.0).draw(rng).ir_mix for _ in range(200))
    assert sum(_life(night_ir=1.0, varied=1.0).draw(rng).ir_mix is not None for _ in range(50)) == 50


def test_blur_is_in_camera_pixels_scaled_to_the_region():
    rng = np.random.default_rng(0)
    life = CameraLife(CameraRange(blurred=1.0, varied=1.0, blur_sigma_px=2.0), SRGB, PETS_NOISE, region_scale=0.5)
    sigmas = [life.draw(rng).blur_sigma_px for _ in range(200)]
    assert 0.0 < max(sigmas) <= 1.0 and max(sigmas) > 0.9


def test_a_high_gain_s_noise_is_what_it_says_at_mid_grey():
    """0.03 of the code range at mid-grey is 7.65 codes of standard deviation on a flat mid-grey window (to first
    order: the response bends more noise than that), the mean kept; the darker the light the less noise in codes
    for shot noise (its variance grows with the light)."""
    flat = np.full((128, 128, 3), 128, np.uint8)
    varied = _life().render(flat, Condition(gain_noise=0.03, shot_share=1.0), np.random.default_rng(0))
    assert float(varied.std()) == pytest.approx(7.65, rel=0.1) and abs(float(varied.mean()) - 128) < 1
    dark = np.full((128, 128, 3), 40, np.uint8)
    noisy_dark = _life().render(dark, Condition(gain_noise=0.1, shot_share=1.0), np.random.default_rng(0))
    read_dark = _life().render(dark, Condition(gain_noise=0.1, shot_share=0.5), np.random.default_rng(0))
    assert float(noisy_dark.std()) < float(read_dark.std())


def test_a_veil_lets_through_its_transmission_and_fills_the_rest_with_airlight():
    """Koschmieder: ``t L + (1 - t) A``, uniform when not patchy: the scene's linear contrast falls to ``t``."""
    window = _window(size=96)
    varied = _life().render(window, Condition(veil_transmission=0.4, airlight=2.0), np.random.default_rng(0))
    before, after = SRGB.decode(window), SRGB.decode(varied)
    assert float(after.std()) == pytest.approx(0.4 * float(before.std()), rel=0.05)
    assert float(after.mean()) == pytest.approx(0.4 * float(before.mean()) + 0.6 * 2.0 * float(before.mean()),
                                                rel=0.05)


def test_rain_and_snow_brighten_a_few_pixels_more_as_they_thicken():
    window = _window(size=128)
    brightened = []
    for density in (0.001, 0.006):
        varied = _life().render(window, Condition(precipitation=(density, 1.0, 3.0, 10.0, 1.0)),
                                np.random.default_rng(0))
        change = varied.astype(int) - window.astype(int)
        assert (change >= -2).all()  # particles only add light here (brighter than this window's ground)
        brightened.append(float(np.mean(change.max(axis=2) > 10)))
    assert 0.0 < brightened[0] < brightened[1] < 0.5


@pytest.mark.parametrize("kernel", [disc_kernel(0.3), disc_kernel(4.5), line_kernel(1.0, 0.0), line_kernel(17.0, 33.0)])
def test_defocus_and_shake_kernels_keep_the_light(kernel):
    assert kernel.dtype == np.float32 and kernel.sum() == pytest.approx(1.0, abs=1e-5) and (kernel >= 0).all()
    assert kernel.shape[0] == kernel.shape[1] and kernel.shape[0] % 2 == 1


def test_a_shake_spreads_the_light_along_its_direction_only():
    kernel = line_kernel(12.0, 0.0)  # along x
    centre = kernel.shape[0] // 2
    assert kernel[centre].sum() > 0.9 and np.count_nonzero(kernel[centre] > 0.01) >= 12
    disc = disc_kernel(4.0)
    assert np.count_nonzero(disc > 0) == pytest.approx(np.pi * 4.5 ** 2, rel=0.15)


def test_each_blur_kind_is_drawn_and_a_kind_sized_nothing_is_not():
    rng = np.random.default_rng(0)
    conditions = [_life(blurred=1.0, varied=1.0).draw(rng) for _ in range(300)]
    for name in ("blur_sigma_px", "defocus_px", "shake_px"):
        assert sum(getattr(condition, name) > 0 for condition in conditions) > 60
    no_shake = [_life(blurred=1.0, varied=1.0, shake_px=0.0).draw(rng) for _ in range(100)]
    assert not any(condition.shake_px for condition in no_shake)


def test_hostile_windows_stay_finite_codes():
    life = _life(varied=1.0, blurred=1.0, compressed=1.0, noisy=1.0, veiled=1.0, precipitation=1.0)
    rng = np.random.default_rng(1)
    for window in (np.zeros((32, 48, 3), np.uint8), np.full((32, 48, 3), 255, np.uint8), np.ones((1, 1, 3), np.uint8),
                   np.random.default_rng(0).integers(0, 256, (600, 40, 3), dtype=np.uint8)):
        for _ in range(10):
            varied = life.apply(window, rng)
            assert varied.dtype == np.uint8 and varied.shape == window.shape


@pytest.mark.parametrize("fields, field", [({"exposure_stops": (0.5, 1.0)}, "exposure_stops"),
                                           ({"varied": 1.5}, "varied"), ({"jpeg_quality": (90, 30)}, "jpeg_quality"),
                                           ({"white_balance_mired": 500.0}, "white_balance_mired"),
                                           ({"veil_transmission": 0.0}, "veil_transmission"),
                                           ({"gain_noise": -0.1}, "gain_noise"), ({"noisy": 2.0}, "noisy")])
def test_a_range_that_cannot_be_is_refused_by_name(fields, field):
    with pytest.raises(ValueError, match=field):
        CameraRange(**fields)
    name, value = next(iter(fields.items()))
    text = "[" + ", ".join(map(str, value)) + "]" if isinstance(value, tuple) else str(value)
    with pytest.raises(InputError, match=field):
        with_overrides(PRESETS["quick"], [f"train.camera_range={{{name}: {text}}}"])


def test_a_compile_varies_the_camera_and_can_be_told_not_to():
    assert PRESETS["standard"].train.train_config().camera_range == CameraRange()
    assert with_overrides(PRESETS["standard"], ["train.camera_range=null"]).train.train_config().camera_range is None


def test_the_plan_says_each_variation_and_its_cost():
    manifest = {"response": {"name": "srgb"}, "camera_measurements": {"frame_noise": {"model": {"shot": 2e-4,
                                                                                                 "read": 0.0}}}}
    regions = {"r0": {"input_size": [96, 64], "crop_window": [10, 20, 192, 128]}}
    lines = plan_lines(manifest, regions, CameraRange(night_ir=0.0))
    assert "ms per 96x64 window" in lines[0]
    assert any(line.strip().startswith("off  night IR") for line in lines)
    assert any(line.strip().startswith("on   gain noise") for line in lines)
    for variation in ("high gain", "veil", "rain and snow", "blur"):
        assert any(line.strip().startswith(f"on   {variation}") for line in lines), variation
    assert any(line.strip().startswith("off  veil") for line in plan_lines(manifest, regions, CameraRange(veiled=0.0)))
    assert plan_lines(manifest, regions, None)[0].startswith("camera range  off")
    life = camera_life_of({}, regions["r0"], CameraRange(), 0)  # a dataset older than the render plan
    assert life.response.name == "srgb" and life.noise == NoiseModel(0.0, 0.0) and life.region_scale == 0.5
