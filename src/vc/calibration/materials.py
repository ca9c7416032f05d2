"""Albedo priors of the ground: the one place the single-image lighting estimate takes its absolute scale from.

One photograph cannot tell a bright surface under dim light from a dark one under bright light: the lighting
estimate (:mod:`vc.calibration.lighting`) resolves that by assuming what the ground it can see is made of.
It tells two kinds apart by colour — vegetation (green) and everything else, taken as paved ground — and
assumes each kind's diffuse albedo below. The procedural ground of :mod:`vc.render.layout_scene` is drawn
with the same albedos, so a synthetic scene's lighting is recovered without bias from its prior.

Values are linear albedos in the sRGB primaries (luminance in brackets):

* paved ground (0.31): between weathered asphalt (about 0.12-0.20) and concrete paving (0.25-0.40),
  the ranges of the US EPA "Reducing Urban Heat Islands: Compendium of Strategies — Cool Pavements" (2008);
* vegetation (0.12): mown grass in visible light (its broadband 0.25 is mostly near infrared, which an RGB
  camera does not see), a mixture of 70 % green and 30 % dry blades as the procedural grass draws it.
"""

from __future__ import annotations

import numpy as np

#: Linear albedo of paving slabs and paved ground in general (sRGB primaries).
PAVED_ALBEDO = np.array([0.34, 0.31, 0.27])
#: Linear albedos of green and dry grass blades (sRGB primaries).
GREEN_GRASS_ALBEDO = np.array([0.07, 0.12, 0.035])
DRY_GRASS_ALBEDO = np.array([0.13, 0.14, 0.05])
#: The share of dry blades in a lawn, on average (the procedural grass's mean dryness).
MEAN_DRYNESS = 0.3
#: Linear albedo of a lawn seen from a distance: the mean of its blades.
VEGETATION_ALBEDO = (1.0 - MEAN_DRYNESS) * GREEN_GRASS_ALBEDO + MEAN_DRYNESS * DRY_GRASS_ALBEDO
#: A pixel is vegetation when its excess green (2G - R - B) / (R + G + B) in linear light is above this: grass
#: scores 0.3 (dry) to 1.0 (green), grey and beige paving about 0.
VEGETATION_EXCESS_GREEN = 0.25
#: Rec. 709 / sRGB luminance weights of linear RGB.
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Relative luminance of linear sRGB values (..., 3)."""
    return np.asarray(rgb, np.float64) @ LUMINANCE_WEIGHTS


def is_vegetation(linear: np.ndarray) -> np.ndarray:
    """Which linear RGB pixels (..., 3) are vegetation (see :data:`VEGETATION_EXCESS_GREEN`)."""
    linear = np.asarray(linear, np.float64)
    total = linear.sum(axis=-1)
    excess = 2.0 * linear[..., 1] - linear[..., 0] - linear[..., 2]
    with np.errstate(invalid="ignore", divide="ignore"):
        return (total > 0) & (excess > VEGETATION_EXCESS_GREEN * total)


def ground_albedo_prior(linear: np.ndarray) -> np.ndarray:
    """The assumed albedo (..., 3) of ground pixels of linear RGB ``linear`` (..., 3), by their kind."""
    return np.where(is_vegetation(linear)[..., None], VEGETATION_ALBEDO, PAVED_ALBEDO)
