"""The effects plan: each effect on only when the scene calls for it, with the reason; unknowns refused."""

from __future__ import annotations

import pytest
from scene_factory import base_scene, write_scene

from vc.errors import InputError
from vc.render.effects import plan_effects
from vc.scenes.loader import load_scene
from vc.scenes.schema import Lighting


def _decisions(tmp_path, **changes) -> dict:
    scene = load_scene(write_scene(tmp_path, {**base_scene(), **changes}))
    lighting = scene.lighting if isinstance(scene.lighting, Lighting) else Lighting()
    return {decision.name: decision for decision in plan_effects(scene, lighting)}


def test_auto_switches_on_what_the_scene_needs(tmp_path) -> None:
    decisions = _decisions(tmp_path, lighting={"sun_strength": 0.0})
    assert not decisions["shadows"].on and "no direct sun" in decisions["shadows"].reason
    assert not decisions["motion_blur"].on and "not simulated" in decisions["motion_blur"].reason
    sunny = _decisions(tmp_path / "sunny", lighting={"sun_strength": 2.0, "sun_elevation_deg": 30.0})
    assert sunny["shadows"].on


def test_an_explicit_list_is_followed(tmp_path) -> None:
    decisions = _decisions(tmp_path, effects=["lens_distortion"], lighting={"sun_strength": 2.0})
    assert not decisions["shadows"].on and "not listed" in decisions["shadows"].reason
    assert decisions["lens_distortion"].on


def test_lens_distortion_cannot_be_left_out_of_a_distorted_camera(tmp_path) -> None:
    with pytest.raises(InputError, match="lens_distortion cannot be left out"):
        _decisions(tmp_path, effects=["shadows"])


def test_asking_for_an_effect_that_is_not_simulated_is_an_input_error(tmp_path) -> None:
    with pytest.raises(InputError, match="motion_blur is not simulated"):
        _decisions(tmp_path, effects=["motion_blur"])
