"""The Mitsuba scene of a layout: textured ground, obstacles, walls, sun and sky.

Geometry is the layout's, exactly (metres, z up, ground z = 0), so that anything rendered into the scene later
stands on the same ground and behind the same obstacles that the labels assume. Appearance is only plausible:
the ground is a procedural texture (paving slabs inside the walkable polygons, grass outside), obstacles and
walls are diffuse with albedos guessed from their names.

Ground: a rectangle over the walkable area (plus :data:`PLAZA_MARGIN_M`) carries the detailed texture; four
large rectangles around it carry a repeating grass tile. Both sample one world-periodic grass pattern on the
same texel grid, so the seam between them cannot be seen.

Lighting: an :class:`~vc.calibration.lighting.Illumination`, irradiances in linear pixel units (a white
Lambertian surface facing the sun reflects ``sun / pi`` from the sun, and a horizontal one ``sky / pi`` from the
sky), so the sunlit/shadow contrast on the ground is ``1 + sun * sin(elevation) / sky``. The sun is a
``directional`` emitter; the sky is a ``constant`` emitter of the same horizontal irradiance whatever its model:
Mitsuba's ``sunsky`` is a clear sky in physical units (neither overcast nor the camera's exposure), and for the
ground, which is all this scene is compared on, a CIE overcast sky differs from a uniform one only where walls
hide part of it. The people renderer (:mod:`vc.render.people_renderer`) shades people with the sky's own
distribution.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import cv2
import numpy as np

from vc.calibration.lighting import Illumination
from vc.calibration.materials import DRY_GRASS_ALBEDO, GREEN_GRASS_ALBEDO, MEAN_DRYNESS, PAVED_ALBEDO
from vc.render.mitsuba_setup import mitsuba
from vc.scenes.layout import Box, Cylinder, Layout, Wall

if TYPE_CHECKING:
    import mitsuba as mi

Albedo = tuple[float, float, float]

#: Ground texel size (metres): 2.5 cm keeps 30 cm slabs sharp a few metres from a surveillance camera.
GROUND_TEXEL_M = 0.025
#: Largest side of the detailed ground texture; a larger area gets coarser texels instead.
MAX_TEXTURE_PX = 4096
#: Detailed ground texture extends this far beyond the walkable area.
PLAZA_MARGIN_M = 6.0
#: How far the grass-covered ground extends beyond the detailed texture: past any surveillance camera's view.
GROUND_EXTENT_M = 1000.0
#: Period of the repeating grass pattern (metres).
GRASS_PERIOD_M = 16.0
#: Paving slabs (metres, x by y), laid in running bond (every other row shifted by half a slab), and the
#: width of the joints between them.
SLAB_M = (0.6, 0.3)
JOINT_M = 0.015
#: Width of the kerb stones along the edge of the walkable area.
KERB_M = 0.12

#: Linear albedos (sRGB primaries); paving and grass are the lighting estimate's priors (vc.calibration.materials).
PAVING_ALBEDO = PAVED_ALBEDO
GRASS_ALBEDO = GREEN_GRASS_ALBEDO
JOINT_ALBEDO = np.array([0.16, 0.15, 0.14])
KERB_ALBEDO = np.array([0.39, 0.38, 0.36])
DEFAULT_ALBEDO: Albedo = (0.30, 0.30, 0.30)
WALL_ALBEDO: Albedo = (0.32, 0.14, 0.09)
#: Albedo hints by obstacle name (the first keyword found in the lower-cased name wins).
NAMED_ALBEDOS: tuple[tuple[tuple[str, ...], Albedo], ...] = (
    (("lamp", "post", "pole", "light"), (0.05, 0.05, 0.055)),
    (("bollard",), (0.12, 0.12, 0.13)),
    (("bench", "wood"), (0.28, 0.16, 0.08)),
    (("planter", "concrete"), (0.40, 0.38, 0.35)),
    (("kiosk", "booth", "stand"), (0.50, 0.40, 0.26)),
    (("tree", "trunk"), (0.10, 0.07, 0.05)),
    (("bin", "trash"), (0.06, 0.12, 0.08)),
)


def obstacle_albedo(name: str | None, default: Albedo = DEFAULT_ALBEDO) -> Albedo:
    """A plausible albedo for an obstacle called ``name`` (``default`` when the name says nothing)."""
    lowered = (name or "").lower()
    for keywords, albedo in NAMED_ALBEDOS:
        if any(keyword in lowered for keyword in keywords):
            return albedo
    return default


# --- procedural ground texture ------------------------------------------------------------------------------
def _periodic_noise(rng: np.random.Generator, shape: tuple[int, int], feature_px: float) -> np.ndarray:
    """Smooth zero-mean, unit-variance noise with features of about ``feature_px``, periodic in both axes.

    Low-pass filtering white noise in the Fourier domain makes the result tile seamlessly by construction.
    """
    spectrum = np.fft.rfft2(rng.standard_normal(shape))
    ky = np.fft.fftfreq(shape[0])[:, None]
    kx = np.fft.rfftfreq(shape[1])[None, :]
    noise = np.fft.irfft2(spectrum * np.exp(-((kx**2 + ky**2) * (math.pi * feature_px) ** 2)), s=shape)
    return (noise - noise.mean()) / max(float(noise.std()), 1e-12)


def grass_tile(texel_m: float, seed: int) -> np.ndarray:
    """One period of the grass pattern, (N, N, 3) linear albedo; texel (i, j) covers world
    ``[j, j + 1) * texel_m`` in x and ``[i, i + 1) * texel_m`` in y, modulo the period."""
    rng = np.random.default_rng([seed, 1])
    n = max(8, round(GRASS_PERIOD_M / texel_m))
    patches = _periodic_noise(rng, (n, n), 2.0 / texel_m)
    tufts = _periodic_noise(rng, (n, n), 0.15 / texel_m)
    blades = rng.standard_normal((n, n))
    brightness = np.exp(0.22 * patches + 0.12 * tufts + 0.10 * blades)
    dryness = np.clip(MEAN_DRYNESS + 0.25 * _periodic_noise(rng, (n, n), 3.0 / texel_m), 0.0, 1.0)[..., None]
    hue = (1.0 - dryness) * GRASS_ALBEDO + dryness * DRY_GRASS_ALBEDO
    return (hue * brightness[..., None]).astype(np.float32)


def _walkable_mask(layout: Layout, origin: np.ndarray, texel_m: float, shape: tuple[int, int]) -> np.ndarray:
    """Fraction of each texel inside the walkable area (anti-aliased rasterisation), (H, W) float."""
    shift = 4  # cv2 fixed-point coordinates: 1/16 texel
    mask = np.zeros(shape, np.uint8)
    for polygon in layout.walkable:
        # Texel (i, j) has its centre at origin + (j + 0.5, i + 0.5) * texel_m; cv2 puts centres at integers.
        pixels = (np.asarray(polygon) - origin) / texel_m - 0.5
        cv2.fillPoly(mask, [np.round(pixels * (1 << shift)).astype(np.int32)], 255, cv2.LINE_AA, shift)
    return mask.astype(np.float32) / 255.0


def _joint_coverage(position: np.ndarray, period: float, texel_m: float) -> np.ndarray:
    """Fraction of a texel centred at ``position`` covered by the joints at multiples of ``period``."""
    distance = np.abs(position / period - np.round(position / period)) * period
    return np.clip((JOINT_M / 2 - distance) / texel_m + 0.5, 0.0, 1.0)


def _paving(inside: np.ndarray, origin: np.ndarray, texel_m: float, rng: np.random.Generator) -> np.ndarray:
    """Paving slabs with joints, per-slab tone, low-frequency weathering, grain, and kerb stones along the edge
    of ``inside`` (the walkable texels), (H, W, 3) linear albedo."""
    shape = inside.shape
    slab_x, slab_y = SLAB_M
    ys = origin[1] + (np.arange(shape[0]) + 0.5) * texel_m
    xs = origin[0] + (np.arange(shape[1]) + 0.5) * texel_m
    row = np.floor(ys / slab_y).astype(int)
    shifted_xs = xs[None, :] - (row % 2)[:, None] * (slab_x / 2)
    column = np.floor(shifted_xs / slab_x).astype(int)
    tones = rng.normal(1.0, 0.035, (row.max() - row.min() + 1, column.max() - column.min() + 1))
    tone = tones[(row - row.min())[:, None], column - column.min()]
    joints = np.maximum(_joint_coverage(ys, slab_y, texel_m)[:, None],
                        _joint_coverage(shifted_xs, slab_x, texel_m))[..., None]
    weathering = np.exp(0.10 * _periodic_noise(rng, shape, 1.5 / texel_m))
    grain = np.exp(0.05 * rng.standard_normal(shape))
    slabs = PAVING_ALBEDO * (tone * weathering * grain)[..., None]
    albedo = (1.0 - joints) * slabs + joints * JOINT_ALBEDO * weathering[..., None]
    kerb_px = KERB_M / texel_m
    distance_to_edge = cv2.distanceTransform(inside.astype(np.uint8), cv2.DIST_L2, 5)
    kerb = inside & (distance_to_edge <= kerb_px)
    albedo[kerb] = KERB_ALBEDO * grain[kerb, None]
    return albedo


def ground_texture(layout: Layout, seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    """The detailed ground texture around the walkable area.

    Returns ``(albedo, origin, texel_m)``: linear albedo (H, W, 3) float32 whose row ``i``, column ``j`` covers
    the world square with lower corner ``origin + (j, i) * texel_m`` (rows go along +y). ``origin`` is a whole
    number of texels, so the grass here lines up with :func:`grass_tile` repeated over the rest of the ground.
    """
    x0, y0, x1, y1 = layout.walkable_area().bounds
    extent = max(x1 - x0, y1 - y0) + 2 * PLAZA_MARGIN_M
    texel_m = max(GROUND_TEXEL_M, extent / MAX_TEXTURE_PX)
    first = np.floor((np.array([x0, y0]) - PLAZA_MARGIN_M) / texel_m).astype(int)
    last = np.ceil((np.array([x1, y1]) + PLAZA_MARGIN_M) / texel_m).astype(int)
    shape = (int(last[1] - first[1]), int(last[0] - first[0]))
    origin = first * texel_m
    tile = grass_tile(texel_m, seed)
    rows = (first[1] + np.arange(shape[0])) % tile.shape[0]
    cols = (first[0] + np.arange(shape[1])) % tile.shape[1]
    grass = tile[rows[:, None], cols[None, :]]
    coverage = _walkable_mask(layout, origin, texel_m, shape)
    paving = _paving(coverage > 0.5, origin, texel_m, np.random.default_rng([seed, 2]))
    coverage = coverage[..., None]
    albedo = coverage * paving + (1.0 - coverage) * grass
    return albedo.astype(np.float32), origin, texel_m


# --- shapes -------------------------------------------------------------------------------------------------
def _diffuse(albedo: Sequence[float]) -> dict:
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [float(a) for a in albedo]}}


def _bitmap(albedo: np.ndarray, wrap_mode: str, to_uv: mi.ScalarTransform3f | None = None) -> dict:
    """A bitmap texture of linear albedo (``raw``: no sRGB decoding), held in memory rather than in a file."""
    texture = {"type": "bitmap", "bitmap": mitsuba().Bitmap(albedo), "raw": True, "filter_type": "bilinear",
               "wrap_mode": wrap_mode}
    if to_uv is not None:
        texture["to_uv"] = to_uv
    return texture


def _ground_rectangle(low: np.ndarray, high: np.ndarray, texture: dict) -> dict:
    """A z = 0 rectangle from ``low`` to ``high`` (x, y); its uv runs 0 -> 1 along +x and +y, and a bitmap's
    first row is at v = 0, so texture rows run along +y."""
    centre, half = (low + high) / 2, (high - low) / 2
    to_world = mitsuba().ScalarTransform4f().translate([*centre, 0.0]).scale([*half, 1.0])
    return {"type": "rectangle", "to_world": to_world, "bsdf": {"type": "diffuse", "reflectance": texture}}


def uniform_ground_shapes(layout: Layout, albedo: float) -> dict[str, dict]:
    """The ground plane as one grey rectangle of ``albedo`` past any camera's view (for shading renders)."""
    x0, y0, x1, y1 = layout.walkable_area().bounds
    low, high = np.array([x0, y0]) - GROUND_EXTENT_M, np.array([x1, y1]) + GROUND_EXTENT_M
    centre, half = (low + high) / 2, (high - low) / 2
    to_world = mitsuba().ScalarTransform4f().translate([*centre, 0.0]).scale([*half, 1.0])
    return {"ground": {"type": "rectangle", "to_world": to_world, "bsdf": _diffuse([albedo] * 3)}}


def ground_shapes(layout: Layout, seed: int) -> dict[str, dict]:
    """The ground plane: the detailed rectangle around the walkable area and four grass rectangles around it."""
    albedo, low, texel_m = ground_texture(layout, seed)
    high = low + np.array([albedo.shape[1], albedo.shape[0]]) * texel_m
    shapes = {"ground_plaza": _ground_rectangle(low, high, _bitmap(albedo, "clamp"))}
    tile = grass_tile(texel_m, seed)
    period = tile.shape[0] * texel_m
    (x0, y0), (x1, y1) = low, high
    (outer_x0, outer_y0), (outer_x1, outer_y1) = low - GROUND_EXTENT_M, high + GROUND_EXTENT_M
    strips = {
        "ground_south": ([outer_x0, outer_y0], [outer_x1, y0]),
        "ground_north": ([outer_x0, y1], [outer_x1, outer_y1]),
        "ground_west": ([outer_x0, y0], [x0, y1]),
        "ground_east": ([x1, y0], [outer_x1, y1]),
    }
    for name, (strip_low, strip_high) in strips.items():
        strip_low, strip_high = np.asarray(strip_low), np.asarray(strip_high)
        # uv (0..1 over the strip) -> world / period, so the tile repeats on the same world grid as the plaza.
        to_uv = mitsuba().ScalarTransform3f().translate(strip_low / period).scale((strip_high - strip_low) / period)
        shapes[name] = _ground_rectangle(strip_low, strip_high, _bitmap(tile, "repeat", to_uv))
    return shapes


def _cuboid(center: Sequence[float], size: Sequence[float], yaw_deg: float, albedo: Sequence[float]) -> dict:
    """Mitsuba's cube spans [-1, 1]^3: scale by half the size, turn about z, move to the centre."""
    to_world = (mitsuba().ScalarTransform4f().translate([float(c) for c in center])
                .rotate([0.0, 0.0, 1.0], yaw_deg).scale([s / 2 for s in size]))
    return {"type": "cube", "to_world": to_world, "bsdf": _diffuse(albedo)}


def box_shape(box: Box) -> dict:
    return _cuboid(box.center, box.size, box.yaw, obstacle_albedo(box.name))


def cylinder_shapes(cylinder: Cylinder) -> list[dict]:
    """Mitsuba's cylinder is an open tube: a disk closes its top (the bottom stands on the ground)."""
    mi = mitsuba()
    bsdf = _diffuse(obstacle_albedo(cylinder.name))
    x, y = cylinder.base
    tube = {"type": "cylinder", "p0": [x, y, 0.0], "p1": [x, y, cylinder.height], "radius": cylinder.radius,
            "bsdf": bsdf}
    cap_to_world = mi.ScalarTransform4f().translate([x, y, cylinder.height]).scale(cylinder.radius)
    return [tube, {"type": "disk", "to_world": cap_to_world, "bsdf": bsdf}]


def wall_shape(wall: Wall) -> dict:
    """A wall is a thin box along its centre line, brick-coloured unless its name hints otherwise."""
    (x0, y0), (x1, y1) = wall.start, wall.end
    albedo = obstacle_albedo(wall.name, default=WALL_ALBEDO)
    return _cuboid([(x0 + x1) / 2, (y0 + y1) / 2, wall.height / 2],
                   [math.hypot(x1 - x0, y1 - y0), wall.thickness, wall.height],
                   math.degrees(math.atan2(y1 - y0, x1 - x0)), albedo)


def emitters(illumination: Illumination) -> dict[str, dict]:
    """Sun and sky emitters (see the module docstring for units); a sun below the horizon is left out."""
    result = {}
    if illumination.has_sun:
        result["sun"] = {"type": "directional", "direction": (-illumination.towards_sun()).tolist(),
                         "irradiance": {"type": "rgb", "value": list(illumination.sun_rgb)}}
    if max(illumination.sky_rgb) > 0:
        radiance = [value / math.pi for value in illumination.sky_rgb]
        result["sky"] = {"type": "constant", "radiance": {"type": "rgb", "value": radiance}}
    return result


def layout_scene_dict(layout: Layout, illumination: Illumination, sensor: dict, seed: int = 0, max_depth: int = 4,
                      ground_albedo: float | None = None) -> dict:
    """A Mitsuba scene dict: ground, obstacles and walls of ``layout`` lit by ``illumination``, seen by ``sensor``.

    ``seed`` drives the procedural ground texture only (the renderer's own seed goes to ``mi.render``);
    ``ground_albedo`` replaces that texture by a uniform grey ground (a shading render).
    """
    scene: dict = {"type": "scene", "integrator": {"type": "path", "max_depth": max_depth}, "sensor": sensor}
    scene.update(ground_shapes(layout, seed) if ground_albedo is None else uniform_ground_shapes(layout, ground_albedo))
    for index, obstacle in enumerate(layout.obstacles):
        if isinstance(obstacle, Box):
            scene[f"obstacle_{index}"] = box_shape(obstacle)
        else:
            tube, cap = cylinder_shapes(obstacle)
            scene[f"obstacle_{index}"], scene[f"obstacle_{index}_cap"] = tube, cap
    for index, wall in enumerate(layout.walls):
        scene[f"wall_{index}"] = wall_shape(wall)
    scene.update(emitters(illumination))
    return scene
