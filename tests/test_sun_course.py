"""The sun's course over the background's day: its positions, the effect on only where a scene says where and when
its background was taken and the background shows a sun, the background relit so that the layout's shadows move
with the sun, and samples drawn under the positions with the same bytes whatever order they are rendered in."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import EXAMPLE_SCENES
from scene_factory import base_scene, write_scene

from vc.calibration.compression import JpegEstimate
from vc.calibration.lighting import illumination_from_strengths
from vc.calibration.noise import NoiseEstimate, NoiseModel
from vc.calibration.sharpness import BlurEstimate
from vc.errors import InputError
from vc.render.camera_measurements import CameraMeasurements
from vc.render.effects import Evidence, SunCourse, plan_effects
from vc.render.people_renderer import ground_shadow_points
from vc.render.plan import plan_render
from vc.render.sun_course import MIN_ELEVATION_DEG, STEP_HOURS, moved_sun, shading_ratio, sun_positions
from vc.render.synthesis import RegionSynthesizer, SynthesisSettings
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions
from vc.scenes.schema import SolarLighting

pytestmark = pytest.mark.xdist_group("anny")

DATED_DEMO = EXAMPLE_SCENES / "demo_dated" / "scene.yaml"
#: Where and when the dated demo's background was taken: its sun stands at azimuth 215, elevation 40 in the scene.
DEMO_SOLAR = yaml.safe_load(DATED_DEMO.read_text())["lighting"]
#: A camera measured clean: no effect but the light's is called for.
NO_NOISE = NoiseEstimate(NoiseModel(0.0, 0.0), 0.0, 0, "flat blocks")
CLEAN = CameraMeasurements("the background", NO_NOISE, NO_NOISE, JpegEstimate(None, False, {}),
                           JpegEstimate(None, False, {}), BlurEstimate(0.0, 0))
#: A point just inside the top of the demo's kiosk, near its front right corner: its shadow lies inside the kiosk's,
#: on ground the kiosk does not hide from the camera under either sun tested.
KIOSK_TOP = np.array([[8.8, 11.6, 2.4]])
#: Open paving, in the sun whenever the kiosk's shadow falls elsewhere.
OPEN_GROUND = np.array([[0.0, 5.0, 0.0]])


def test_the_positions_run_through_the_background_day_from_the_photographed_one() -> None:
    positions = sun_positions(SolarLighting(**DEMO_SOLAR))
    photographed, moved = positions[0], positions[1:]
    assert photographed.photographed and not any(position.photographed for position in moved)
    assert photographed.azimuth_deg == pytest.approx(215.0, abs=0.5)
    assert photographed.elevation_deg == pytest.approx(40.0, abs=0.5)
    hours = [int(position.time[11:13]) for position in moved]
    assert hours == list(range(hours[0], hours[-1] + 1, int(STEP_HOURS)))
    assert hours[0] <= 9 and hours[-1] >= 17  # a May day in Reading: morning to evening
    assert min(position.elevation_deg for position in moved) >= MIN_ELEVATION_DEG
    # The sun turns from the east through the south to the west: its shadows swing round by more than 180 degrees.
    turn = np.unwrap(np.radians([position.azimuth_deg for position in moved]))
    assert abs(np.degrees(turn[-1] - turn[0])) > 180


def test_a_polar_night_has_no_position_to_move_to() -> None:
    polar = SolarLighting(location=[78.2, 15.6], time="2009-12-21T12:00:00+01:00", north_deg=0.0)
    assert len(sun_positions(polar)) == 1


def _decision(tmp_path: Path, lighting, sun: float, effects="auto"):
    scene = load_scene(write_scene(tmp_path, {**base_scene(), "lighting": lighting, "effects": effects}))
    evidence = Evidence(scene, plan_regions(scene), illumination_from_strengths(215.0, 40.0, sun, 1.0), None, CLEAN)
    return {decision.name: decision for decision in plan_effects(evidence)}["sun_course"], evidence


def test_the_course_is_followed_only_where_the_scene_says_where_and_when_and_the_sun_shines(tmp_path) -> None:
    decision, _ = _decision(tmp_path / "solar", DEMO_SOLAR, sun=4.0)
    assert decision.on and "where and when" in decision.reason
    assert decision.parameters["positions"][0]["photographed"] and len(decision.parameters["positions"]) >= 5

    decision, _ = _decision(tmp_path / "auto", "auto", sun=4.0)
    assert not decision.on and "where and when" in decision.reason
    decision, _ = _decision(tmp_path / "overcast", DEMO_SOLAR, sun=0.0)
    assert not decision.on and "no direct sun" in decision.reason


def test_listing_the_course_without_where_and_when_is_refused(tmp_path) -> None:
    scene = load_scene(write_scene(tmp_path, {**base_scene(), "effects": ["lens_distortion", "sun_course"]}))
    evidence = Evidence(scene, plan_regions(scene), illumination_from_strengths(215.0, 40.0, 4.0, 1.0), None, CLEAN)
    with pytest.raises(InputError) as error:
        SunCourse.requested(evidence)
    assert error.value.field == "effects" and "where and when" in str(error.value)


@pytest.fixture(scope="module")
def solar_plan():
    scene = load_scene(DATED_DEMO)
    return scene, plan_render(scene, plan_regions(scene), time_costs=False)


def _pixel(scene, point: np.ndarray) -> tuple[int, int]:
    u, v = np.round(scene.camera.project(point).uv[0]).astype(int)
    return int(v), int(u)


@pytest.mark.slow
def test_the_layout_shadows_move_with_the_sun_on_the_relit_background(solar_plan) -> None:
    scene, plan = solar_plan
    estimated = plan.illumination
    assert estimated.sun_azimuth_deg == pytest.approx(215.0, abs=0.5)  # the light is estimated with the known sun
    # the sun where it was leaves the background as it is: the two renders take the same samples, which cancel
    assert np.array_equal(shading_ratio(scene, estimated, estimated),
                          np.ones((scene.camera.height, scene.camera.width, 3), np.float32))

    morning = moved_sun(estimated, plan.sun_course[1])
    ratio = shading_ratio(scene, estimated, morning).mean(axis=-1)
    old_shadow = _pixel(scene, ground_shadow_points(KIOSK_TOP, estimated.towards_sun()))
    new_shadow = _pixel(scene, ground_shadow_points(KIOSK_TOP, morning.towards_sun()))
    assert ratio[old_shadow] > 1.5  # the afternoon's shadow is lifted: sun where there was sky alone
    assert ratio[new_shadow] < 0.7  # the morning's is cast
    # open ground keeps its light but for the sun's angle of incidence on it
    expected = (np.sin(np.radians(morning.sun_elevation_deg)) * estimated.sun_to_sky + 1) / \
        (np.sin(np.radians(estimated.sun_elevation_deg)) * estimated.sun_to_sky + 1)
    assert ratio[_pixel(scene, OPEN_GROUND)] == pytest.approx(expected, rel=0.15)


@pytest.mark.slow
def test_samples_are_drawn_under_the_course_with_the_same_bytes_in_any_order(solar_plan, body_model) -> None:
    scene, plan = solar_plan
    region = min(plan_regions(scene), key=lambda region: region.input_size[0] * region.input_size[1])
    settings = SynthesisSettings(spp=4)
    first = RegionSynthesizer(scene, region, body_model, settings, plan)
    samples = [first.sample(index) for index in range(6)]
    # each sample under a position not drawn before built its light (a renderer, the background relit)
    assert sum("sun_course" in sample.timings for sample in samples) >= 2
    # the same sample from a synthesizer that has built none of the course's renderers yet
    again = RegionSynthesizer(scene, region, body_model, settings, plan).sample(5)
    assert np.array_equal(again.image, samples[5].image)
    assert again.annotations == samples[5].annotations
