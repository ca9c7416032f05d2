"""What synthetic people look like: one diffuse albedo and one thickness per body part (skin, hair, clothes,
shoes).

A person 100-200 px tall shows its clothing as a few flat colours, so per-part albedos (linear RGB, what
Mitsuba's ``diffuse`` BSDF takes) carry what matters to a detector: skin tones across ethnicities, hair or a
bald head, garments mostly dark or neutral with some colour, and short sleeves or shorts that bare the
``forearms`` and ``shins`` parts (:data:`vc.render.bodies.BODY_PARTS`).

What people wear follows the scene's ``priors.clothing`` (:data:`WARDROBES`): ``mixed`` (the default, street
clothing of a mild day), ``winter`` (coats and jackets, mostly black, grey and navy; long sleeves and trousers; a
third with a hat or hood) or ``summer`` (short sleeves and bare legs for most, lighter colours). The colour
frequencies are this project's assumptions from street observation, not a published survey: what matters to a
detector is that the renders' people are as dark, as uniform and as covered as the scene's people are.

Thickness is how far a part's surface lies outside the skin (:mod:`vc.render.dressing` moves it out): hair 0.5-2.5
cm (none when bald), a hat or hood 2-5 cm, a shirt to a jacket 0.5-2 cm (a winter coat or parka 1.5-4.5 cm,
summer clothes 2-8 mm), trousers 3-12 mm, shoes 1.2-3 cm (the sole a person stands on). These are this project's
assumptions from garment and footwear dimensions (a street shoe's heel is 2-3 cm, a down parka's loft several
centimetres), not a survey; they matter because a real person's outline is their clothes, not their skin.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import colour
import numpy as np

from vc.render.bodies import BODY_PARTS, Phenotype

# Skin colour as CIELAB (D65) of measured skin, parameterised by the Individual Typology Angle
# ITA = atan((L* - 50) / b*) of Chardon, Cretois & Hourseau, "Skin colour typology and suntanning pathways",
# Int. J. Cosmet. Sci. 13 (1991): very light > 55 deg > light > 41 > intermediate > 28 > tan > 10 > brown > -30 >
# dark. Per ethnicity (african, asian, caucasian), the mean and spread of ITA follow the spectrophotometric
# surveys summarised by Del Bino & Bernerd, "Variations in skin colour and the biological consequences of
# ultraviolet radiation exposure", Br. J. Dermatol. 169 s3 (2013): African skins brown to dark, East Asian
# intermediate to light, European light to very light; b* (yellowness) about 16 and a* (redness) about 11.
# A CIELAB colour of a reflecting surface is its reflectance, so the linear sRGB of L*a*b* is the albedo.
_ITA_MEAN_DEG = np.array([-25.0, 38.0, 47.0])
_ITA_SD_DEG = np.array([18.0, 9.0, 9.0])
_D65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]


def _linear(*srgb_hex: str) -> np.ndarray:
    """sRGB hex colours -> (N, 3) linear RGB (the sRGB transfer function, decoded)."""
    encoded = np.array([[int(code[i:i + 2], 16) for i in (1, 3, 5)] for code in srgb_hex]) / 255.0
    return np.asarray(colour.cctf_decoding(encoded, function="sRGB"), dtype=np.float64)


# Natural hair colours (sRGB: black, dark brown, brown, light brown, dark blond, blond, auburn) and their
# frequencies per ethnicity (african, asian, caucasian).
_HAIR = _linear("#1b1917", "#33261c", "#5a4230", "#7f5f43", "#9c7c52", "#c4a56e", "#7a3d22")
_HAIR_FREQUENCY = np.array([(0.85, 0.70, 0.08), (0.15, 0.27, 0.30), (0.0, 0.02, 0.25), (0.0, 0.01, 0.12),
                            (0.0, 0.0, 0.10), (0.0, 0.0, 0.10), (0.0, 0.0, 0.05)])
_GREY_HAIR = _linear("#5e5b57", "#8f8b86", "#c9c5bd")  # salt and pepper, grey, white


def _palette(frequency: dict[str, int]) -> tuple[np.ndarray, np.ndarray]:
    """Linear colours (N, 3) and their probabilities (N,) of sRGB hex colours with relative frequencies."""
    weights = np.array(list(frequency.values()), dtype=np.float64)
    return _linear(*frequency), weights / weights.sum()


# Clothing colours (sRGB) and frequencies: street clothing is mostly black, grey, navy, denim, white and beige,
# with a minority of saturated colours.
_UPPER = _palette({
    "#2a2a2a": 18, "#3c3c3e": 10, "#7f7f80": 8, "#b5b5b3": 5, "#e6e4df": 12, "#1f2a44": 10, "#5a7da6": 5,
    "#c2b280": 5, "#5c4033": 4, "#4b5320": 4, "#6d1a24": 4, "#b22222": 3, "#e1ad01": 2, "#1f5fbf": 3, "#e7a1b0": 2,
    "#2e8b57": 2, "#e07b24": 1, "#5b3a78": 2})
_LOWER = _palette({
    "#2c3e5c": 12, "#3b5998": 8, "#6a89b0": 6, "#2a2a2a": 25, "#3c3c3e": 12, "#1f2a44": 8, "#c2b280": 10,
    "#5c4033": 4, "#7f7f80": 5, "#d8d0c0": 3, "#4b5320": 3, "#e6e4df": 2})
_SHOES = _palette({
    "#1e1e1e": 40, "#3b2a20": 12, "#e8e8e6": 20, "#6f6f6f": 10, "#1f2a44": 5, "#a0784f": 6, "#b22222": 3,
    "#1f5fbf": 4})

DRESS = 0.25  # of bare shins on a woman: a dress, one colour from shoulders to knees

# Ranges (m) of each covering's thickness over the skin (module docstring).
HAIR_THICKNESS_M = (0.005, 0.025)
HEADWEAR_THICKNESS_M = (0.02, 0.05)
LOWER_THICKNESS_M = (0.003, 0.012)
SHOE_THICKNESS_M = (0.012, 0.03)


@dataclass(frozen=True)
class Wardrobe:
    """What the people of a scene wear: garment palettes, how thick the upper garment is, how often arms and
    shins are bare, and how often (``headwear``) a hat or hood covers the hair, its colour from
    ``headwear_colours``."""

    upper: tuple[np.ndarray, np.ndarray]
    lower: tuple[np.ndarray, np.ndarray]
    shoes: tuple[np.ndarray, np.ndarray]
    short_sleeves: float  # probability of bare forearms
    bare_shins: float  # shorts, or a skirt or dress above the knee
    upper_thickness_m: tuple[float, float]  # range of the torso's and sleeves' garment thickness
    headwear: float = 0.0
    headwear_colours: tuple[np.ndarray, np.ndarray] | None = None


_MIXED = Wardrobe(_UPPER, _LOWER, _SHOES, short_sleeves=0.35, bare_shins=0.15, upper_thickness_m=(0.005, 0.02))
# Winter outerwear: coats, parkas and jackets over trousers; boots and dark shoes.
_WINTER = Wardrobe(
    upper=_palette({
        "#1c1c1c": 30, "#333335": 14, "#55565a": 8, "#1f2a44": 14, "#3b2a20": 6, "#4b5320": 5, "#b39b72": 5,
        "#5e1a24": 4, "#808083": 5, "#a52a2a": 2, "#27408b": 2, "#c8c8c6": 3, "#1e3d2f": 2}),
    lower=_palette({
        "#1c1c1c": 30, "#333335": 14, "#2c3e5c": 14, "#3b5998": 8, "#1f2a44": 8, "#5c4033": 4, "#a89a7a": 4,
        "#6a6a6c": 6}),
    shoes=_palette({"#151515": 50, "#3b2a20": 20, "#e8e8e6": 10, "#5a5a5a": 10, "#8a6440": 10}),
    short_sleeves=0.0, bare_shins=0.0, upper_thickness_m=(0.015, 0.045), headwear=0.35,
    headwear_colours=_palette({"#151515": 50, "#333335": 20, "#1f2a44": 15, "#6f6f6f": 10, "#9b1b1b": 5}))
# Summer: short sleeves and bare legs for most, more white and light colours than the mild-day mix.
_SUMMER = Wardrobe(
    upper=_palette({
        "#e6e4df": 22, "#b5b5b3": 8, "#2a2a2a": 12, "#1f2a44": 8, "#9ec3e6": 8, "#5a7da6": 6, "#e7a1b0": 5,
        "#c2b280": 6, "#b22222": 5, "#e1ad01": 4, "#2e8b57": 4, "#e07b24": 3, "#7f7f80": 6, "#5b3a78": 3}),
    lower=_LOWER, shoes=_SHOES, short_sleeves=0.75, bare_shins=0.45, upper_thickness_m=(0.002, 0.008))
#: ``priors.clothing`` -> what the scene's people wear.
WARDROBES: dict[str, Wardrobe] = {"mixed": _MIXED, "winter": _WINTER, "summer": _SUMMER}


@dataclass(frozen=True)
class Appearance:
    """Linear-RGB diffuse albedo and thickness over the skin (m) of every body part of one person."""

    part_albedo: dict[str, tuple[float, float, float]]
    part_thickness_m: dict[str, float]

    def to_dict(self) -> dict:
        return {"part_albedo": {part: [round(c, 4) for c in rgb] for part, rgb in self.part_albedo.items()},
                "part_thickness_m": {part: round(value, 4) for part, value in self.part_thickness_m.items()}}


def sample_appearance(rng: np.random.Generator, phenotype: Phenotype, wardrobe: Wardrobe = _MIXED) -> Appearance:
    """Skin from the ethnicity mixture, hair from ethnicity and age (greying, male baldness), clothes from the
    ``wardrobe``, and how thick each covering is (drawn last)."""
    ethnicity = np.asarray(phenotype.ethnicity, dtype=np.float64)
    skin = _skin_albedo(rng, ethnicity)

    male, age = phenotype.gender, phenotype.age_years
    bald = rng.random() < 0.01 + 0.5 * male * np.clip((age - 25.0) / 50.0, 0.0, 1.0)
    greying = np.clip((age - 35.0) / 40.0, 0.0, 1.0) ** 1.5 * 0.9
    if rng.random() < greying:
        hair = _GREY_HAIR[int(np.clip((age - 40.0) / 15.0 + rng.random(), 0.0, 2.0))]  # whiter with age
    else:
        weights = _HAIR_FREQUENCY @ ethnicity
        hair = _HAIR[rng.choice(len(_HAIR), p=weights / weights.sum())]
    hair = _jitter(rng, hair, 0.2)
    upper, lower, shoes = (_jitter(rng, _pick(rng, palette), 0.15)
                           for palette in (wardrobe.upper, wardrobe.lower, wardrobe.shoes))
    short_sleeves = rng.random() < wardrobe.short_sleeves
    bare_shins = rng.random() < wardrobe.bare_shins
    headwear = bool(wardrobe.headwear) and rng.random() < wardrobe.headwear
    if headwear:
        hair, bald = _jitter(rng, _pick(rng, wardrobe.headwear_colours), 0.15), False
    if bare_shins and rng.random() < DRESS * (1.0 - male):
        lower = upper
    albedo = {"skin": skin, "hair": skin if bald else hair, "upper": upper, "lower": lower, "shoes": shoes,
              "forearms": skin if short_sleeves else upper, "shins": skin if bare_shins else lower}
    hair_m, upper_m, lower_m, shoes_m = (float(rng.uniform(*span)) for span in (
        HEADWEAR_THICKNESS_M if headwear else HAIR_THICKNESS_M, wardrobe.upper_thickness_m, LOWER_THICKNESS_M,
        SHOE_THICKNESS_M))
    thickness = {"skin": 0.0, "hair": 0.0 if bald else hair_m, "upper": upper_m, "lower": lower_m, "shoes": shoes_m,
                 "forearms": 0.0 if short_sleeves else upper_m, "shins": 0.0 if bare_shins else lower_m}
    return Appearance({part: tuple(float(c) for c in albedo[part]) for part in BODY_PARTS},
                      {part: thickness[part] for part in BODY_PARTS})


def vertex_albedo(model_parts: np.ndarray, appearance: Appearance) -> np.ndarray:
    """(V, 3) float32 linear albedo of each vertex, from its :data:`BODY_PARTS` label."""
    table = np.array([appearance.part_albedo[part] for part in BODY_PARTS], dtype=np.float32)
    return table[np.asarray(model_parts)]


def vertex_thickness(model_parts: np.ndarray, appearance: Appearance) -> np.ndarray:
    """(V,) float64 thickness (m) over the skin of each vertex, from its :data:`BODY_PARTS` label."""
    table = np.array([appearance.part_thickness_m[part] for part in BODY_PARTS], dtype=np.float64)
    return table[np.asarray(model_parts)]


def _skin_albedo(rng: np.random.Generator, ethnicity: np.ndarray) -> np.ndarray:
    ita = np.radians(np.clip(rng.normal(ethnicity @ _ITA_MEAN_DEG, ethnicity @ _ITA_SD_DEG), -60.0, 65.0))
    b = np.clip(rng.normal(16.0, 3.0), 9.0, 24.0)
    a = np.clip(rng.normal(11.0, 2.5), 5.0, 18.0)
    lightness = np.clip(50.0 + b * np.tan(ita), 25.0, 78.0)
    xyz = colour.Lab_to_XYZ(np.array([lightness, a, b]), _D65)
    return np.clip(colour.XYZ_to_sRGB(xyz, apply_cctf_encoding=False), 0.01, 0.9)


def _pick(rng: np.random.Generator, palette: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    colours, probabilities = palette
    return colours[rng.choice(len(colours), p=probabilities)]


def _jitter(rng: np.random.Generator, rgb: Sequence[float], spread: float) -> np.ndarray:
    """The same colour lighter or darker (log-normal factor), and a little more or less saturated."""
    rgb = np.asarray(rgb) * np.exp(rng.normal(0.0, spread))
    grey = rgb.mean()
    return np.clip(grey + (rgb - grey) * np.exp(rng.normal(0.0, 0.15)), 0.005, 0.85)
