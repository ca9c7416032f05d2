"""Per-part albedos: valid, deterministic, skin tones following ethnicity, bald heads, sleeves and shorts."""

from __future__ import annotations

import json

import colour
import numpy as np

from vc.render.appearance import Appearance, sample_appearance, vertex_albedo
from vc.render.bodies import BODY_PARTS, Phenotype, sample_phenotype


def appearances(count: int, seed: int = 0, **changes) -> list[Appearance]:
    rng = np.random.default_rng(seed)
    result = []
    for _ in range(count):
        phenotype = sample_phenotype(rng)
        result.append(sample_appearance(rng, Phenotype(**{**phenotype.__dict__, **changes})))
    return result


def test_albedos_are_valid_linear_rgb_for_every_part() -> None:
    for appearance in appearances(300):
        assert set(appearance.part_albedo) == set(BODY_PARTS)
        rgb = np.array(list(appearance.part_albedo.values()))
        assert np.all((rgb > 0.0) & (rgb < 1.0))
        assert json.loads(json.dumps(appearance.to_dict())) == appearance.to_dict()


def test_sampling_is_deterministic() -> None:
    assert appearances(50, seed=4) == appearances(50, seed=4)
    assert appearances(50, seed=4) != appearances(50, seed=5)


def test_skin_is_darker_for_african_than_for_caucasian_ancestry() -> None:
    def mean_skin(ethnicity: tuple[float, float, float]) -> float:
        return float(np.mean([a.part_albedo["skin"][1] for a in appearances(400, seed=1, ethnicity=ethnicity)]))

    african, mixed, caucasian = mean_skin((0.9, 0.05, 0.05)), mean_skin((0.45, 0.1, 0.45)), mean_skin((0.05, 0.05, 0.9))
    assert african < mixed < caucasian
    assert african < 0.5 * caucasian


def test_bald_heads_take_the_skin_colour_and_garments_end_where_parts_do() -> None:
    sample = appearances(2000, seed=2, gender=1.0, age_years=70.0)
    bald = [a for a in sample if a.part_albedo["hair"] == a.part_albedo["skin"]]
    assert 0.2 < len(bald) / len(sample) < 0.6  # old men are often bald
    assert sum(a.part_albedo["hair"] == a.part_albedo["skin"] for a in appearances(500, seed=2, gender=0.0)) < 25
    for a in sample:
        assert a.part_albedo["forearms"] in (a.part_albedo["skin"], a.part_albedo["upper"])
        assert a.part_albedo["shins"] in (a.part_albedo["skin"], a.part_albedo["lower"])
    assert 0.2 < np.mean([a.part_albedo["forearms"] == a.part_albedo["skin"] for a in sample]) < 0.5
    assert 0.05 < np.mean([a.part_albedo["shins"] == a.part_albedo["skin"] for a in sample]) < 0.25


def test_clothing_is_mostly_dark_or_neutral() -> None:
    for part in ("upper", "lower"):
        linear = np.array([a.part_albedo[part] for a in appearances(1000, seed=3)])
        srgb = np.asarray(colour.cctf_encoding(linear, function="sRGB"))
        value, saturation = srgb.max(1), 1.0 - srgb.min(1) / srgb.max(1)
        assert np.mean((value < 0.3) | (saturation < 0.3)) > 0.5, part  # denim blue counts as colour
        assert 0.05 < np.mean((value > 0.4) & (saturation > 0.5)) < 0.35, part


def test_vertex_albedo_looks_up_each_vertex_part() -> None:
    appearance = appearances(1)[0]
    parts = np.array([index for index in range(len(BODY_PARTS)) for _ in range(3)], dtype=np.uint8)
    albedo = vertex_albedo(parts, appearance)
    assert albedo.shape == (len(parts), 3) and albedo.dtype == np.float32
    for vertex, part in enumerate(parts):
        np.testing.assert_allclose(albedo[vertex], appearance.part_albedo[BODY_PARTS[part]], rtol=1e-6)
