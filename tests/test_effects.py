"""The effects registry: each effect on only when the scene calls for it (with the reason and its parameters),
an effect that is off never constructed, explicit lists followed or refused with a reason, and each effect doing
to a sample what it says (noise of the measured variance, never added twice; blur that spreads; compression
that stays deterministic)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scene_factory import base_scene, write_scene

from vc.calibration.compression import JpegEstimate
from vc.calibration.lighting import illumination_from_strengths
from vc.calibration.noise import NoiseEstimate, NoiseModel
from vc.calibration.sharpness import BlurEstimate
from vc.errors import InputError
from vc.render import effects as registry
from vc.render.camera_measurements import CameraMeasurements
from vc.render.effects import (
    REGISTRY,
    Compression,
    EffectDecision,
    Evidence,
    MotionBlur,
    MovingPerson,
    OpticalBlur,
    SampleLayers,
    SensorNoise,
    build_effects,
    plan_effects,
)
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions

NO_NOISE = NoiseEstimate(NoiseModel(0.0, 0.0), 0.0, 0, "flat blocks")
CLEAN = CameraMeasurements("the background", NO_NOISE, NO_NOISE, JpegEstimate(None, False, {}),
                           JpegEstimate(None, False, {}), BlurEstimate(0.0, 0))


def _noise(sigma_8bit: float, read: float) -> NoiseEstimate:
    return NoiseEstimate(NoiseModel(0.0, read), sigma_8bit, 500, "temporal variance")


#: A camera whose frames are noisy, compressed and blurred, over a clean (temporal-median) background.
DEGRADED = CameraMeasurements("24 frames of a video", _noise(3.0, 0.01), NO_NOISE, JpegEstimate(40, True, {}),
                              JpegEstimate(None, False, {}), BlurEstimate(1.6, 900))


def _evidence(tmp_path, measured=CLEAN, sun: float = 0.0, **changes) -> Evidence:
    scene = load_scene(write_scene(tmp_path, {**base_scene(), **changes}))
    return Evidence(scene, plan_regions(scene), illumination_from_strengths(135.0, 45.0, sun, 1.0), None, measured)


def _decisions(evidence: Evidence) -> dict[str, EffectDecision]:
    return {decision.name: decision for decision in plan_effects(evidence)}


def test_auto_switches_on_what_the_scene_needs(tmp_path) -> None:
    clean = _decisions(_evidence(tmp_path))
    assert clean["shadows"].on and "contact shadows" in clean["shadows"].reason  # overcast: the sky's own
    for name in ("sensor_noise", "jpeg", "optical_blur", "motion_blur", "vignetting", "defocus"):
        assert not clean[name].on, name
    assert "exposure time is not known" in clean["motion_blur"].reason
    degraded = _decisions(_evidence(tmp_path / "degraded", DEGRADED, sun=3.0))
    assert degraded["shadows"].on and degraded["shadows"].parameters["sun_to_sky"] > 0
    assert degraded["sensor_noise"].on and "3.00 8-bit levels" in degraded["sensor_noise"].reason
    assert degraded["jpeg"].on and degraded["jpeg"].parameters == {
        "quality": 40, "chroma_subsampling": True, "measured_on": "24 frames of a video"}
    # 1.6 px against the renderer's own (box sampling and the distortion warp, 0.6 px): on
    assert degraded["optical_blur"].on and set(degraded["optical_blur"].parameters["added_sigma_px"]) == {
        region.name for region in plan_regions(load_scene(tmp_path / "degraded" / "scene.yaml"))}


def test_an_effect_that_is_off_is_never_constructed(tmp_path, monkeypatch) -> None:
    evidence = _evidence(tmp_path)
    decisions = plan_effects(evidence)

    def refuse(self, *args, **kwargs):
        raise AssertionError(f"{type(self).__name__} was constructed although it is off")

    for effect in REGISTRY:
        monkeypatch.setattr(effect, "__init__", refuse)
    assert build_effects(decisions, evidence.scene, evidence.regions[0]) == []


def test_an_explicit_list_is_followed(tmp_path) -> None:
    decisions = _decisions(_evidence(tmp_path, DEGRADED, effects=["lens_distortion", "jpeg"], sun=2.0))
    assert not decisions["shadows"].on and "not listed" in decisions["shadows"].reason
    assert not decisions["sensor_noise"].on
    assert decisions["jpeg"].on and decisions["jpeg"].reason.startswith("listed")
    assert decisions["lens_distortion"].on


def test_a_listed_effect_with_nothing_to_simulate_is_refused(tmp_path) -> None:
    with pytest.raises(InputError, match="jpeg is listed, but no block compression found"):
        _decisions(_evidence(tmp_path, CLEAN, effects=["lens_distortion", "jpeg"]))
    with pytest.raises(InputError, match="defocus is not simulated"):
        _decisions(_evidence(tmp_path / "defocus", CLEAN, effects=["lens_distortion", "defocus"]))


def test_lens_distortion_cannot_be_left_out_of_a_distorted_camera(tmp_path) -> None:
    with pytest.raises(InputError, match="lens_distortion cannot be left out"):
        _decisions(_evidence(tmp_path, effects=["shadows"]))


def test_motion_blur_follows_the_exposure_time(tmp_path) -> None:
    camera = {**base_scene()["camera"], "exposure_s": 0.04}
    decisions = _decisions(_evidence(tmp_path, camera=camera))
    assert decisions["motion_blur"].on and decisions["motion_blur"].parameters["walker_travel_px"] > 0.5
    short = {**base_scene()["camera"], "exposure_s": 0.0001}
    assert not _decisions(_evidence(tmp_path / "short", camera=short))["motion_blur"].on


# --- what each effect does to a sample ----------------------------------------------------------------------
@pytest.fixture(scope="module")
def region_context(tmp_path_factory):
    scene = load_scene(write_scene(tmp_path_factory.mktemp("scene"), base_scene()))
    return scene, plan_regions(scene)[0]


def _layers(region, people: int = 1) -> SampleLayers:
    width, height = region.input_size
    coverage = np.zeros((height, width, people), np.float32)
    coverage[height // 4:3 * height // 4, width // 2 - 3:width // 2 + 3, 0] = 1.0
    return SampleLayers(beauty=coverage[..., :1] * np.float32([0.3, 0.2, 0.1]), coverage=coverage,
                        shadow=np.ones((height, width, 3), np.float32),
                        people=[MovingPerson(np.array([0.0, 5.0, 0.9]), np.array([2.0, 0.0, 0.0]))] * people)


def test_sensor_noise_adds_the_frames_variance_less_the_backgrounds(region_context) -> None:
    scene, region = region_context
    decision = EffectDecision("sensor_noise", True, "test", {"frames": {"shot": 0.0, "read": 0.02},
                                                             "background": {"shot": 0.0, "read": 0.012}})
    effect = SensorNoise(decision, scene, region)
    width, height = region.input_size
    linear = np.full((height, width, 3), 0.2, np.float32)
    photographed = effect.on_linear(linear, np.zeros((height, width), np.float32), np.random.default_rng(1))
    rendered = effect.on_linear(linear, np.ones((height, width), np.float32), np.random.default_rng(1))
    # Unit noise resized from the camera's resolution to the input keeps its variance up to the resize's
    # averaging; the ratio between the two cases is exact.
    assert rendered.std() / photographed.std() == pytest.approx(0.02 / np.sqrt(0.02**2 - 0.012**2), rel=0.03)
    assert np.isfinite(rendered).all()
    again = effect.on_linear(linear, np.ones((height, width), np.float32), np.random.default_rng(1))
    np.testing.assert_array_equal(rendered, again)


def test_compression_is_deterministic_and_changes_the_image(region_context) -> None:
    scene, region = region_context
    effect = Compression(EffectDecision("jpeg", True, "test", {"quality": 20, "chroma_subsampling": True}), scene,
                         region)
    width, height = region.input_size
    image = (np.random.default_rng(0).random((height, width, 3)) * 255).astype(np.uint8)
    compressed = effect.on_encoded(image, np.random.default_rng(0))
    assert compressed.dtype == np.uint8 and compressed.shape == image.shape
    assert np.abs(compressed.astype(int) - image).mean() > 5
    np.testing.assert_array_equal(compressed, effect.on_encoded(image, np.random.default_rng(1)))


def test_optical_blur_spreads_the_people_and_keeps_their_coverage(region_context) -> None:
    scene, region = region_context
    effect = OpticalBlur(EffectDecision("optical_blur", True, "test", {"scene_sigma_px": 3.0,
                                                                       "added_sigma_px": {region.name: 2.0}}),
                         scene, region)
    layers = _layers(region)
    before = layers.coverage.sum()
    effect.on_layers(layers, np.random.default_rng(0))
    assert effect.sigma > 0
    assert (layers.coverage[..., 0] > 0.01).sum() > (_layers(region).coverage[..., 0] > 0).sum()
    assert layers.coverage.sum() == pytest.approx(before, rel=0.01)


def test_motion_blur_smears_a_walker_along_their_path(region_context) -> None:
    scene, region = region_context
    effect = MotionBlur(EffectDecision("motion_blur", True, "test", {"exposure_s": 0.5}), scene, region)
    layers = _layers(region)
    columns_before = (layers.coverage[..., 0].sum(axis=0) > 0).sum()
    rows_before = (layers.coverage[..., 0].sum(axis=1) > 0).sum()
    effect.on_layers(layers, np.random.default_rng(0))
    assert (layers.coverage[..., 0].sum(axis=0) > 1e-3).sum() > columns_before  # walking along x: wider
    assert (layers.coverage[..., 0].sum(axis=1) > 1e-3).sum() <= rows_before + 4
    assert layers.coverage.sum() == pytest.approx(_layers(region).coverage.sum(), rel=0.02)


def test_the_registry_lists_every_effect_the_schema_accepts() -> None:
    from vc.scenes.schema import EFFECT_NAMES

    assert {effect.name for effect in REGISTRY} == set(EFFECT_NAMES)
    assert [effect.stage for effect in REGISTRY] == sorted((effect.stage for effect in REGISTRY),
                                                           key=registry.STAGES.index)


def test_planned_effects_record_their_parameters(tmp_path) -> None:
    decisions = plan_effects(_evidence(tmp_path, DEGRADED))
    for decision in decisions:
        assert isinstance(decision.to_dict()["parameters"], dict)
        assert replace(decision, ms_per_sample=1.0).to_dict()["ms_per_sample"] == 1.0


def _fit_with_falloff(darkening: float, vegetation_offset: float = 0.0):
    from vc.render.relight import LightingFit

    height, width = 120, 160
    ys, xs = np.indices((height, width))
    radius2 = ((xs - 79.5) ** 2 + (ys - 59.5) ** 2) / (np.hypot(width, height) / 2) ** 2
    vegetation = xs < 40  # a strip of lawn down the left side, darker than its prior
    background = 0.3 * (1.0 - darkening) ** radius2 * np.where(vegetation, np.exp(vegetation_offset), 1.0)
    rendered = np.full((height, width, 3), 0.3, np.float32)
    return LightingFit(rendered, np.ones((height, width), bool), vegetation, background.astype(np.float32), [],
                       np.ones(3))


def test_vignetting_is_the_radial_fall_off_the_ground_kinds_do_not_explain(region_context) -> None:
    scene, _ = region_context
    camera = scene.camera.resized(160, 120)
    darkening, explained = registry.fit_vignetting(camera, _fit_with_falloff(0.3), stride=1)
    assert darkening == pytest.approx(0.3, abs=0.03) and explained > 0.9
    # a lawn darker than its prior is an offset of its kind, not a lens
    darkening, explained = registry.fit_vignetting(camera, _fit_with_falloff(0.0, vegetation_offset=-0.5), stride=1)
    assert abs(darkening) < 0.03 and explained < registry.MIN_VIGNETTING_EXPLAINED
