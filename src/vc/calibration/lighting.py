"""Sun and sky estimated from the one background image and the layout's known geometry.

Units (one place): irradiances are in the background's *linear pixel units*. A Lambertian surface of albedo
``rho`` under irradiance ``E`` shows ``rho * E / pi`` in the decoded (linear) background, so an estimate in these
units renders people exactly as bright as the camera would record them. ``sky`` is the irradiance the sky gives
an unoccluded horizontal surface; ``sun`` the irradiance of the sun on a surface facing it. Colours are the
camera's own linear RGB: the camera's white balance is part of the light's colour, so people rendered under it
come out with the colour cast the camera gives real people. Directions: azimuth in the ground plane from +x
towards +y (counter-clockwise seen from above), elevation above the horizon.

The estimate, step by step:

1. **Known ground.** The background is decoded to linear light. Pixels whose ray meets the ground inside the
   walkable area, not behind a known solid (obstacle or wall) and not clipped, are ground the layout vouches
   for; :mod:`vc.calibration.materials` assumes their albedo by kind (vegetation or paved).
2. **Sun direction.** From ``lighting: {location, time}`` through a solar-position library when the scene gives
   them; else searched: for each candidate direction the known solids' shadows are cast onto the ground and
   projected into the image, and the candidate scores by how much darker the predicted shadows are than a ring
   of ground around them, and over how many pixels (:func:`shadow_score`). The best
   candidate counts as a sun only when its shadows are clearly dark (:data:`MIN_SUN_CONTRAST`), clearly
   darker than a typical direction's (:data:`MIN_SUN_PROMINENCE`: ground next to any solid is a little darker
   under any sky, since the solid hides part of it), and dark for every well-measured solid alike
   (:data:`MIN_SHADOW_AGREEMENT`: one solid's shadow on ground dark for another reason is not a sun); otherwise
   the scene is overcast (no direct sun).
3. **Sun over sky.** Lit ground receives ``sky + sun * sin(elevation)``, shadowed ground of the same material
   ``sky``: the lit/shadow ratio ``r`` gives ``sun / sky = (r - 1) / sin(elevation)``, per colour channel.
4. **Absolute scale** (exposure and white balance): ``sky`` per channel is the median over lit known ground of
   ``pi * L / (rho * (1 + sun/sky * sin(elevation)))``. :mod:`vc.render.relight` refines it against a
   path-traced re-render of the empty scene (sky occlusion by solids, light bounced between surfaces).

An overcast sky is modelled as the CIE standard overcast sky (zenith three times as bright as the horizon);
a sky with a sun as uniform (its circumsolar brightening is part of the sun).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from datetime import datetime

import colour
import cv2
import numpy as np
import shapely

from vc.calibration.camera import Camera
from vc.calibration.materials import ground_albedo_prior, is_vegetation, luminance

RGB = tuple[float, float, float]

#: Colours of sunlight and skylight for lighting given as strengths (linear, about unit luminance): a warm sun
#: and a blue sky, as an explicit ``lighting:`` block in a scene file renders them.
SUN_COLOUR: RGB = (1.0, 0.95, 0.86)
SKY_COLOUR: RGB = (0.78, 0.90, 1.15)
#: Sky distributions the renderer knows: uniform radiance, or the CIE standard overcast sky.
SKY_MODELS = ("uniform", "cie_overcast")

#: A direct sun needs its shadows at least this much darker than the ground around them (lit/shadow).
MIN_SUN_CONTRAST = 1.25
#: ... and its log contrast this much above the median candidate direction's.
MIN_SUN_PROMINENCE = 0.15
#: ... and every solid whose predicted shadow is measured on at least AGREEING_SHADOW_PIXELS pixels darkened by
#: at least this share of the solids' mean log contrast: a sun darkens every shadow it casts on open ground
#: alike, so one solid's predicted shadow falling on ground dark for another reason (the contact darkness along a
#: building's base that no layout wall describes, dark paving) is not a sun while another's stays lit
#: (docs/decisions/0055-a-sun-darkens-every-shadow.md).
MIN_SHADOW_AGREEMENT = 0.5
#: A solid's predicted shadow counts toward that agreement when measured on at least this many pixels: a shadow
#: of a few pixels measures its contrast too roughly to veto a sun that the others agree on.
AGREEING_SHADOW_PIXELS = 100
#: Smallest number of pixels of one solid's predicted shadow (and of the ring around it) that is measured.
MIN_SHADOW_PIXELS = 6
#: Width (pixels) of the ring of ground around a predicted shadow that it is compared with.
RING_PX = 4
#: Candidate sun directions: a coarse grid, then a finer one around the best coarse candidate.
COARSE_AZIMUTH_STEP_DEG = 4.0
COARSE_ELEVATION_DEG = tuple(float(e) for e in range(5, 90, 5))
FINE_STEP_DEG = 1.0
#: Linear values at or below this are too dark to measure a ratio on (8-bit sRGB level 1 is 3e-4).
DARKEST_LINEAR = 1e-4
#: Points per edge when a ground polygon's outline is projected (lens distortion bends straight edges).
EDGE_POINTS = 12


# --- what the renderer is lit with ----------------------------------------------------------------------------
@dataclass(frozen=True)
class Illumination:
    """Sun and sky in the background's linear pixel units (see the module docstring)."""

    sky_rgb: RGB
    sun_rgb: RGB = (0.0, 0.0, 0.0)
    sun_azimuth_deg: float = 0.0
    sun_elevation_deg: float = 90.0
    sky_model: str = "uniform"

    def __post_init__(self) -> None:
        values = np.array([*self.sky_rgb, *self.sun_rgb, self.sun_azimuth_deg, self.sun_elevation_deg])
        if not np.isfinite(values).all() or min(*self.sky_rgb, *self.sun_rgb) < 0:
            raise ValueError(f"illumination needs finite, non-negative values, got {self}")
        if self.sky_model not in SKY_MODELS:
            raise ValueError(f"unknown sky model {self.sky_model!r} (expected one of {', '.join(SKY_MODELS)})")

    @property
    def has_sun(self) -> bool:
        return max(self.sun_rgb) > 0 and self.sun_elevation_deg > 0

    def towards_sun(self) -> np.ndarray:
        """Unit vector from the ground towards the sun."""
        return sun_direction(self.sun_azimuth_deg, self.sun_elevation_deg)

    @property
    def sun_to_sky(self) -> float:
        """Sun over sky irradiance, in luminance (0 without a sun)."""
        sky = float(luminance(self.sky_rgb))
        return float(luminance(self.sun_rgb)) / sky if self.has_sun and sky > 0 else 0.0

    def scaled(self, gains: Sequence[float]) -> Illumination:
        """The same light with each colour channel of sun and sky multiplied by ``gains``."""
        gains = np.asarray(gains, np.float64)
        return replace(self, sky_rgb=_rgb(np.asarray(self.sky_rgb) * gains),
                       sun_rgb=_rgb(np.asarray(self.sun_rgb) * gains))

    def to_dict(self) -> dict:
        result = {"sky_model": self.sky_model, "sky_rgb": [round(v, 6) for v in self.sky_rgb]}
        if self.has_sun:
            result.update(sun_rgb=[round(v, 6) for v in self.sun_rgb],
                          sun_azimuth_deg=round(self.sun_azimuth_deg, 2),
                          sun_elevation_deg=round(self.sun_elevation_deg, 2),
                          sun_to_sky=round(self.sun_to_sky, 4))
        else:
            result["sun"] = None
        return result


def _rgb(values: np.ndarray) -> RGB:
    return tuple(float(v) for v in values)  # type: ignore[return-value]


def sun_direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit vector from the ground towards the sun: azimuth from +x towards +y, elevation above the horizon."""
    azimuth, elevation = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                     math.sin(elevation)])


def illumination_from_strengths(sun_azimuth_deg: float, sun_elevation_deg: float, sun_strength: float,
                                sky_strength: float) -> Illumination:
    """Light given as a sun and a sky strength (an explicit ``lighting:`` block): :data:`SUN_COLOUR` and
    :data:`SKY_COLOUR` times the strengths; a sun at or below the horizon gives no direct light."""
    sun = np.asarray(SUN_COLOUR) * (sun_strength if sun_elevation_deg > 0 else 0.0)
    return Illumination(sky_rgb=_rgb(np.asarray(SKY_COLOUR) * sky_strength), sun_rgb=_rgb(sun),
                        sun_azimuth_deg=float(sun_azimuth_deg), sun_elevation_deg=float(sun_elevation_deg))


def sky_gradation(up: np.ndarray, sky_model: str) -> np.ndarray:
    """Sky radiance towards directions whose vertical component is ``up``, relative to a uniform sky of the
    same horizontal irradiance. The CIE overcast sky is ``L_z (1 + 2 up) / 3``; its horizontal irradiance is
    ``7 pi L_z / 9``, so relative to ``E / pi`` it is ``3 (1 + 2 up) / 7``."""
    up = np.clip(np.asarray(up, np.float64), 0.0, 1.0)
    if sky_model == "uniform":
        return np.ones_like(up)
    return 3.0 * (1.0 + 2.0 * up) / 7.0


def solar_position(latitude: float, longitude: float, time: datetime, north_deg: float) -> tuple[float, float]:
    """The sun's (azimuth, elevation) in degrees in the scene's frame at ``time`` (timezone-aware).

    astral gives the azimuth clockwise from geographic north; ``north_deg`` is where north points in the scene
    (counter-clockwise from +x), so the scene azimuth is ``north_deg - astral's``. astral's elevation includes
    atmospheric refraction, as the shadows it is compared with do.
    """
    from astral import Observer
    from astral.sun import azimuth, elevation  # astral: small, pure Python, no pandas (pvlib would pull it in)

    if time.tzinfo is None:
        raise ValueError("the time of day needs a timezone (e.g. 2009-03-20T10:30:00+00:00)")
    observer = Observer(latitude=latitude, longitude=longitude)
    clockwise_from_north = azimuth(observer, time)
    return (north_deg - clockwise_from_north) % 360.0, float(elevation(observer, time))


# --- the ground the layout vouches for -----------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class GroundView:
    """The background in linear light and which of its pixels are known ground (see the module docstring)."""

    linear: np.ndarray  # (H, W, 3) float32
    ground: np.ndarray  # (H, W) bool: known ground
    occluders: np.ndarray  # (H, W) bool: image of a known solid
    luminance: np.ndarray  # (H, W) float32, of ``linear``


def solid_silhouette(camera: Camera, vertices: np.ndarray) -> np.ndarray | None:
    """Pixels (M, 2) of the convex outline of a solid's projected vertices, or None when none is in view."""
    projection = camera.project(vertices)
    uv = projection.uv[projection.ok]
    if len(uv) < 3:
        return None
    return cv2.convexHull(uv.astype(np.float32)).reshape(-1, 2)


def _fill(mask: np.ndarray, polygon_uv: np.ndarray, offset: tuple[int, int] = (0, 0)) -> None:
    shift = 4
    points = np.round((polygon_uv - np.asarray(offset)) * (1 << shift)).astype(np.int32)
    cv2.fillPoly(mask, [points], 1, cv2.LINE_8, shift)


def ground_view(camera: Camera, linear: np.ndarray, clipped: np.ndarray, walkable: shapely.Geometry,
                solids: Sequence[np.ndarray]) -> GroundView:
    """:class:`GroundView` of a background decoded to ``linear``; ``clipped`` marks pixels at the ends of the
    camera's range; ``solids`` are the vertices (N, 3) of each known convex solid."""
    height, width = linear.shape[:2]
    ys, xs = np.indices((height, width))
    hit = camera.ground_from_pixels(np.stack([xs, ys], axis=-1).reshape(-1, 2).astype(np.float64))
    points = np.where(hit.ok[:, None], hit.points, 0.0)
    on_walkable = hit.ok & shapely.contains_xy(walkable, points[:, 0], points[:, 1])
    occluders = np.zeros((height, width), np.uint8)
    for vertices in solids:
        outline = solid_silhouette(camera, vertices)
        if outline is not None:
            _fill(occluders, np.clip(outline, -4 * width, 4 * width))
    occluders = cv2.dilate(occluders, np.ones((3, 3), np.uint8)).astype(bool)
    ground = on_walkable.reshape(height, width) & ~occluders & ~clipped
    return GroundView(linear=linear.astype(np.float32), ground=ground, occluders=occluders,
                      luminance=luminance(linear).astype(np.float32))


# --- shadows of known solids ----------------------------------------------------------------------------------
def ground_shadow_points(points: np.ndarray, towards_sun: np.ndarray) -> np.ndarray:
    """Where the sun's rays through ``points`` (N, 3) meet the ground z = 0."""
    return points - points[:, 2:3] / towards_sun[2] * towards_sun[None, :]


def shadow_outline(vertices: np.ndarray, towards_sun: np.ndarray) -> np.ndarray:
    """The ground polygon (M, 2) a convex solid's shadow covers: the hull of its vertices cast along the sun."""
    cast = ground_shadow_points(vertices, towards_sun)[:, :2]
    return cv2.convexHull(cast.astype(np.float32)).reshape(-1, 2).astype(np.float64)


def _densified(polygon: np.ndarray, points_per_edge: int = EDGE_POINTS) -> np.ndarray:
    following = np.roll(polygon, -1, axis=0)
    steps = np.linspace(0.0, 1.0, points_per_edge, endpoint=False)[None, :, None]
    return (polygon[:, None, :] + steps * (following - polygon)[:, None, :]).reshape(-1, 2)


@dataclass(frozen=True)
class ShadowMeasure:
    """One solid's predicted shadow against the ring of ground around it (medians of linear values)."""

    shadow_pixels: int
    ring_pixels: int
    shadow_rgb: np.ndarray
    ring_rgb: np.ndarray

    @property
    def weight(self) -> float:
        return math.sqrt(min(self.shadow_pixels, self.ring_pixels))

    @property
    def log_contrast(self) -> float:
        """log(ring / shadow) in luminance: positive where the predicted shadow is darker."""
        shadow = max(float(luminance(self.shadow_rgb)), DARKEST_LINEAR)
        return math.log(max(float(luminance(self.ring_rgb)), DARKEST_LINEAR) / shadow)


def measure_shadows(camera: Camera, view: GroundView, solids: Sequence[np.ndarray], towards_sun: np.ndarray
                    ) -> list[ShadowMeasure]:
    """Each solid's predicted shadow for a sun ``towards_sun``, measured on known ground (solids whose shadow or
    ring has too few known-ground pixels are left out)."""
    height, width = view.ground.shape
    windows = []
    shadows = np.zeros((height, width), bool)
    for vertices in solids:
        outline = _densified(shadow_outline(vertices, towards_sun))
        projection = camera.project(np.c_[outline, np.zeros(len(outline))])
        uv = projection.uv[projection.ok]
        if len(uv) < 3:
            continue
        # Far outside the image a shadow is clipped anyway; bound the coordinates for OpenCV's int32 maths.
        uv = np.clip(uv, -4 * max(width, height), 5 * max(width, height))
        x0, y0 = np.maximum(np.floor(uv.min(axis=0)).astype(int) - RING_PX - 1, 0)
        x1, y1 = np.minimum(np.ceil(uv.max(axis=0)).astype(int) + RING_PX + 2, [width, height])
        if x1 <= x0 or y1 <= y0:
            continue
        local = np.zeros((y1 - y0, x1 - x0), np.uint8)
        _fill(local, uv, (x0, y0))
        windows.append((x0, y0, x1, y1, local.astype(bool)))
        shadows[y0:y1, x0:x1] |= local.astype(bool)
    measures = []
    ring_kernel = np.ones((2 * RING_PX + 1, 2 * RING_PX + 1), np.uint8)
    for x0, y0, x1, y1, local in windows:
        known = view.ground[y0:y1, x0:x1]
        in_shadow = local & known
        ring = cv2.dilate(local.astype(np.uint8), ring_kernel).astype(bool) & known & ~shadows[y0:y1, x0:x1]
        shadow_count, ring_count = int(in_shadow.sum()), int(ring.sum())
        if shadow_count < MIN_SHADOW_PIXELS or ring_count < MIN_SHADOW_PIXELS:
            continue
        pixels = view.linear[y0:y1, x0:x1]
        measures.append(ShadowMeasure(shadow_count, ring_count, pixels[in_shadow].mean(axis=0),
                                      pixels[ring].mean(axis=0)))
    return measures


def shadow_score(measures: Sequence[ShadowMeasure]) -> float | None:
    """How well a candidate sun's shadows explain the dark ground: the sum over solids of log contrast times the
    square root of the pixels measured, a t-statistic's shape. A too-high sun predicts a stub of the true shadow
    (dark, but few pixels, and the ring around it catches the rest of the shadow); a too-low one predicts lit
    ground as shadow (many pixels, little contrast); both score lower than the true one. None when nothing could
    be measured."""
    if not measures:
        return None
    return float(sum(m.weight * m.log_contrast for m in measures))


def mean_log_contrast(measures: Sequence[ShadowMeasure]) -> float:
    """The measured shadows' log contrast, averaged with the same weights."""
    weights = np.array([m.weight for m in measures])
    return float(np.dot(weights, [m.log_contrast for m in measures]) / weights.sum())


def shadow_mask(camera: Camera, shape: tuple[int, int], solids: Sequence[np.ndarray], towards_sun: np.ndarray
                ) -> np.ndarray:
    """Pixels (H, W) bool where the ground is in some known solid's shadow for a sun ``towards_sun``."""
    height, width = shape
    shadows = np.zeros(shape, np.uint8)
    for vertices in solids:
        outline = _densified(shadow_outline(vertices, towards_sun))
        projection = camera.project(np.c_[outline, np.zeros(len(outline))])
        uv = projection.uv[projection.ok]
        if len(uv) >= 3:
            _fill(shadows, np.clip(uv, -4 * max(width, height), 5 * max(width, height)))
    return shadows.astype(bool)


def shadow_ratio_rgb(camera: Camera, view: GroundView, solids: Sequence[np.ndarray], towards_sun: np.ndarray
                     ) -> np.ndarray:
    """Lit over shadowed ground per colour channel: medians of all predicted shadows on known ground against
    the ring of known ground around them. Medians, pooled over every solid, keep the antialiased shadow edges and
    the ground's texture out of the ratio (the search's means are for telling directions apart)."""
    shadows = shadow_mask(camera, view.ground.shape, solids, towards_sun)
    ring_kernel = np.ones((2 * RING_PX + 1, 2 * RING_PX + 1), np.uint8)
    ring = cv2.dilate(shadows.astype(np.uint8), ring_kernel).astype(bool) & ~shadows & view.ground
    shadowed = shadows & view.ground
    lit_level = np.median(view.linear[ring], axis=0)
    shadow_level = np.maximum(np.median(view.linear[shadowed], axis=0), DARKEST_LINEAR)
    return lit_level / shadow_level


@dataclass(frozen=True)
class SunSearch:
    """The best candidate sun direction and how it compares with the others."""

    azimuth_deg: float
    elevation_deg: float
    log_contrast: float
    baseline_log_contrast: float
    candidates: int
    measures: list[ShadowMeasure] = field(repr=False)

    @property
    def contrast(self) -> float:
        return math.exp(self.log_contrast)

    @property
    def prominence(self) -> float:
        return self.log_contrast - self.baseline_log_contrast

    @property
    def agreement(self) -> float:
        """The least log contrast of a well-measured solid's shadow (AGREEING_SHADOW_PIXELS) over the mean's: 1
        when every shadow is as dark as the mean, near 0 or below when one stays as light as its surroundings."""
        measured = [m.log_contrast for m in self.measures if m.shadow_pixels >= AGREEING_SHADOW_PIXELS]
        if not measured or self.log_contrast <= 0.0:
            return 1.0
        return min(measured) / self.log_contrast


def search_sun(camera: Camera, view: GroundView, solids: Sequence[np.ndarray]) -> SunSearch | None:
    """The sun direction whose predicted shadows are darkest against their surroundings (coarse grid, then a
    finer one around the best); None when no candidate's shadow falls on measurable known ground."""
    def evaluate(azimuths, elevations) -> list[tuple[float, float, float, list[ShadowMeasure]]]:
        results = []
        for elevation in elevations:
            for azimuth in azimuths:
                measures = measure_shadows(camera, view, solids, sun_direction(azimuth, elevation))
                score = shadow_score(measures)
                if score is not None:
                    results.append((score, azimuth % 360.0, elevation, measures))
        return results

    coarse = evaluate(np.arange(0.0, 360.0, COARSE_AZIMUTH_STEP_DEG), COARSE_ELEVATION_DEG)
    if not coarse:
        return None
    _, azimuth, elevation, _ = max(coarse, key=lambda result: result[0])
    elevation_step = COARSE_ELEVATION_DEG[1] - COARSE_ELEVATION_DEG[0]
    fine = evaluate(azimuth + np.arange(-COARSE_AZIMUTH_STEP_DEG, COARSE_AZIMUTH_STEP_DEG + 0.5, FINE_STEP_DEG),
                    [e for e in np.arange(elevation - elevation_step, elevation + elevation_step + 0.5, FINE_STEP_DEG)
                     if 1.0 <= e <= 89.0])
    _, azimuth, elevation, measures = max(coarse + fine, key=lambda result: result[0])
    baseline = float(np.median([mean_log_contrast(result[3]) for result in coarse]))
    return SunSearch(float(azimuth), float(elevation), mean_log_contrast(measures), baseline,
                     len(coarse) + len(fine), measures)


# --- the estimate ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LightingEstimate:
    """The estimated light and the evidence for it (all of it goes into the render manifest)."""

    illumination: Illumination
    sun_source: str  # "location and time", "cast shadows" or "none"
    reason: str  # one sentence: why this sun (or none)
    ground_pixels: int
    vegetation_share: float
    shadow: dict | None  # the shadow measurements behind the sun/sky ratio
    white_point: dict  # the sky's colour: chromaticity and correlated colour temperature

    def to_dict(self) -> dict:
        return {**asdict(self), "illumination": self.illumination.to_dict()}


def white_point(rgb: Sequence[float]) -> dict:
    """Chromaticity (CIE 1931 xy) and correlated colour temperature of a linear sRGB colour (colour-science)."""
    rgb = np.maximum(np.asarray(rgb, np.float64), 1e-9)
    xyz = colour.RGB_to_XYZ(rgb, colour.RGB_COLOURSPACES["sRGB"], apply_cctf_decoding=False)
    xy = colour.XYZ_to_xy(xyz)
    cct = float(colour.xy_to_CCT(xy, method="McCamy 1992"))
    return {"xy": [round(float(v), 4) for v in xy], "cct_k": round(cct) if math.isfinite(cct) else None}


def sky_from_ground(view: GroundView, sun_to_sky_rgb: np.ndarray, elevation_deg: float, lit: np.ndarray
                    ) -> np.ndarray:
    """Sky irradiance per channel from the ``lit`` known ground and the albedo prior (step 4)."""
    pixels = view.linear[lit].astype(np.float64)
    gain = 1.0 + sun_to_sky_rgb * max(math.sin(math.radians(elevation_deg)), 0.0)
    implied = math.pi * pixels / (ground_albedo_prior(pixels) * gain)
    return np.median(implied, axis=0)


def lit_ground(camera: Camera, view: GroundView, solids: Sequence[np.ndarray], towards_sun: np.ndarray | None
               ) -> np.ndarray:
    """Known ground outside every known solid's shadow, with a ring's margin (all known ground without a sun)."""
    if towards_sun is None:
        return view.ground
    shadows = shadow_mask(camera, view.ground.shape, solids, towards_sun).astype(np.uint8)
    shadows = cv2.dilate(shadows, np.ones((2 * RING_PX + 1,) * 2, np.uint8)).astype(bool)
    return view.ground & ~shadows


@dataclass(frozen=True)
class SunFinding:
    """What the background says about the sun: its direction and lit/shadow ratio per channel (both None for no
    sun), where it came from ("location and time", "cast shadows" or "none"), why, and the shadow measurements."""

    direction: tuple[float, float] | None
    ratio_rgb: np.ndarray | None
    source: str
    reason: str
    shadow: dict | None = None


def _no_sun(reason: str, shadow: dict | None = None) -> SunFinding:
    return SunFinding(None, None, "none", reason, shadow)


def sun_from_position(camera: Camera, view: GroundView, solids: Sequence[np.ndarray], azimuth: float,
                      elevation: float) -> SunFinding:
    """The sun where the scene's location and time put it, if its shadows show it is out (step 2, given)."""
    if elevation <= 0:
        return _no_sun(f"the sun is below the horizon at the scene's location and time ({elevation:.1f} deg)")
    towards = sun_direction(azimuth, elevation)
    measures = measure_shadows(camera, view, solids, towards)
    if not measures:
        return _no_sun("the sun is up at the scene's location and time, but no known solid's shadow falls on "
                       "visible ground, so its strength cannot be measured: the sky alone lights the scene")
    contrast = math.exp(mean_log_contrast(measures))
    shadow = {"contrast": round(contrast, 4), "solids": len(measures),
              "shadow_pixels": sum(m.shadow_pixels for m in measures)}
    if contrast < MIN_SUN_CONTRAST:
        return _no_sun(f"the sun's predicted shadows are only {contrast:.2f}x darker than the ground around them "
                       f"(< {MIN_SUN_CONTRAST}): overcast", shadow)
    return SunFinding((azimuth, elevation), shadow_ratio_rgb(camera, view, solids, towards), "location and time",
                      f"sun from the location and time; its shadows are {contrast:.2f}x darker than the ground",
                      shadow)


def sun_from_shadows(camera: Camera, view: GroundView, solids: Sequence[np.ndarray]) -> SunFinding:
    """The sun searched for in the known solids' shadows (step 2, searched)."""
    search = search_sun(camera, view, solids)
    if search is None:
        return _no_sun("no known solid casts a shadow on visible ground for any sun direction: no sun can be "
                       "measured")
    shadow = {"contrast": round(search.contrast, 4), "prominence": round(search.prominence, 4),
              "agreement": round(search.agreement, 4),
              "azimuth_deg": search.azimuth_deg, "elevation_deg": search.elevation_deg,
              "candidates": search.candidates, "solids": len(search.measures),
              "shadow_pixels": sum(m.shadow_pixels for m in search.measures)}
    if search.contrast < MIN_SUN_CONTRAST or search.prominence < MIN_SUN_PROMINENCE:
        return _no_sun(f"no direct sun: the darkest predicted shadows are {search.contrast:.2f}x darker than the "
                       f"ground around them (a sun needs >= {MIN_SUN_CONTRAST}x and "
                       f"{math.exp(MIN_SUN_PROMINENCE):.2f}x over a typical direction, found "
                       f"{math.exp(search.prominence):.2f}x): overcast", shadow)
    if search.agreement < MIN_SHADOW_AGREEMENT:
        return _no_sun(f"no direct sun: the darkest predicted shadows are {search.contrast:.2f}x darker than the "
                       f"ground around them, but one solid's is only {search.contrast ** search.agreement:.2f}x "
                       f"(a sun darkens every shadow alike): dark ground, not shadow", shadow)
    direction = (search.azimuth_deg, search.elevation_deg)
    return SunFinding(direction, shadow_ratio_rgb(camera, view, solids, sun_direction(*direction)), "cast shadows",
                      f"the known solids' shadows are {search.contrast:.2f}x darker than the ground around them for "
                      f"the sun at azimuth {search.azimuth_deg:.0f} deg, elevation {search.elevation_deg:.0f} deg",
                      shadow)


def estimate_lighting(camera: Camera, view: GroundView, solids: Sequence[np.ndarray],
                      known_sun: tuple[float, float] | None = None) -> LightingEstimate:
    """Sun and sky from the background (see the module docstring); ``known_sun`` is (azimuth, elevation) from
    the scene's location and time, when it gives them."""
    ground_count = int(view.ground.sum())
    if ground_count == 0:
        raise ValueError("no known ground in view: the walkable area is not visible in the background")
    sun = (sun_from_position(camera, view, solids, *known_sun) if known_sun is not None
           else sun_from_shadows(camera, view, solids))
    if sun.direction is None:
        sky = sky_from_ground(view, np.zeros(3), 90.0, view.ground)
        illumination = Illumination(sky_rgb=_rgb(sky), sky_model="cie_overcast")
    else:
        azimuth, elevation = sun.direction
        sun_to_sky_rgb = np.maximum(sun.ratio_rgb - 1.0, 0.0) / math.sin(math.radians(elevation))
        lit = lit_ground(camera, view, solids, sun_direction(azimuth, elevation))
        sky = sky_from_ground(view, sun_to_sky_rgb, elevation, lit if lit.any() else view.ground)
        illumination = Illumination(sky_rgb=_rgb(sky), sun_rgb=_rgb(sky * sun_to_sky_rgb),
                                    sun_azimuth_deg=float(azimuth), sun_elevation_deg=float(elevation),
                                    sky_model="uniform")
    return LightingEstimate(illumination=illumination, sun_source=sun.source, reason=sun.reason,
                            ground_pixels=ground_count,
                            vegetation_share=round(float(is_vegetation(view.linear[view.ground]).mean()), 4),
                            shadow=sun.shadow, white_point=white_point(illumination.sky_rgb))
