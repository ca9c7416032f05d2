"""Per-part albedos: valid, deterministic, skin tones following ethnicity, bald heads, sleeves and shorts."""

from __future__ import annotations

import json
from typing import get_args

import colour
import numpy as np

from vc.render.appearance import WARDROBES, Appearance, sample_appearance, vertex_albedo
from vc.render.bodies import BODY_PARTS, Phenotype, sample_phenotype
from vc.scenes.schema import Priors


def appearances(count: int, seed: int = 0, clothing: str | None = None, **changes) -> list[Appearance]:
    rng = np.random.default_rng(seed)
    result = []
    for _ in range(count):
        phenotype = Phenotype(**{**sample_phenotype(rng).__dict__, **changes})
        result.append(sample_appearance(rng, phenotype) if clothing is None
                      else sample_appearance(rng, phenotype, WARDROBES[clothing]))
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


def luminances(sample: list[Appearance], part: str) -> np.ndarray:
    return np.array([a.part_albedo[part] for a in sample]) @ np.array([0.2126, 0.7152, 0.0722])


def test_every_clothing_a_scene_can_name_has_a_wardrobe() -> None:
    assert set(get_args(Priors.model_fields["clothing"].annotation)) == set(WARDROBES)
    assert Priors().clothing == "mixed"


def test_the_mixed_wardrobe_is_the_default_and_draws_the_same_people() -> None:
    # scenes without priors.clothing keep the bytes of their renders
    assert appearances(200, seed=6) == appearances(200, seed=6, clothing="mixed")


def test_winter_people_are_darker_and_covered_and_summer_people_lighter_and_bare() -> None:
    mixed, winter, summer = (appearances(1500, seed=7, clothing=name) for name in ("mixed", "winter", "summer"))
    for part in ("upper", "lower"):
        assert np.median(luminances(winter, part)) < 0.7 * np.median(luminances(mixed, part)), part
    assert np.percentile(luminances(winter, "upper"), 75) < 0.12  # a light coat is the exception
    assert np.median(luminances(summer, "upper")) > 2.0 * np.median(luminances(mixed, "upper"))

    def bare(sample: list[Appearance], part: str, garment: str) -> float:
        return float(np.mean([a.part_albedo[part] == a.part_albedo["skin"] != a.part_albedo[garment]
                              for a in sample]))

    assert bare(winter, "forearms", "upper") == 0.0 and bare(winter, "shins", "lower") == 0.0
    assert bare(summer, "forearms", "upper") > 0.6 and bare(summer, "shins", "lower") > 0.35
    # hats and hoods: a third of winter heads wear the headwear palette's colours, dark as the coats
    covered = np.mean([a.part_albedo["hair"] != a.part_albedo["skin"] for a in winter])
    assert covered > np.mean([a.part_albedo["hair"] != a.part_albedo["skin"] for a in mixed])
    assert np.median(luminances(winter, "hair")) < 0.06


def test_thickness_follows_what_covers_each_part() -> None:
    sample = appearances(2000, seed=6, clothing="winter", gender=1.0, age_years=70.0)
    for a in sample:
        t = a.part_thickness_m
        assert t["skin"] == 0.0 and 0.012 <= t["shoes"] <= 0.03
        assert (t["hair"] == 0.0) == (a.part_albedo["hair"] == a.part_albedo["skin"])  # bald heads are bare
        assert t["forearms"] == t["upper"] and t["shins"] == t["lower"]  # winter: sleeves and trousers
        assert 0.015 <= t["upper"] <= 0.045
    headwear = np.array([a.part_thickness_m["hair"] > 0.025 for a in sample])
    assert 0.2 < headwear.mean() < 0.4  # only a hat or hood is thicker than hair
    for a in appearances(500, seed=7, clothing="summer"):
        t = a.part_thickness_m
        assert t["forearms"] == (0.0 if a.part_albedo["forearms"] == a.part_albedo["skin"] else t["upper"])
        assert t["shins"] == (0.0 if a.part_albedo["shins"] == a.part_albedo["skin"] else t["lower"])
