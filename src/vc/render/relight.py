"""The light a scene's samples are rendered under, resolved once per render, and how well it explains the
background.

* An explicit ``lighting:`` block (sun and sky strengths) is used as given.
* ``lighting: auto`` and ``lighting: {location, time, north_deg}`` are estimated from the background
  (:mod:`vc.calibration.lighting`: sun direction, sun/sky ratio, colour and a first absolute scale from the
  ground albedo prior), then the scale is refined here against a path-traced re-render of the empty scene:
  the layout with a uniform grey ground is rendered under the estimate (sky hidden by obstacles and walls, light
  bounced between surfaces, the solids' own shadows), its ground is given the prior albedo of what the
  background shows there, and the one gain per colour channel that best matches the background's linear
  radiance on the known ground (median ratio) is the camera's exposure and white balance.

The comparison (:class:`LightingFit`) reports, per region, the background's median linear luminance on the
region's known ground against the re-render's: what ``vc-scene light`` draws and what the render manifest
records.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import shapely

from vc.calibration.camera import Camera
from vc.calibration.lighting import (
    GroundView,
    Illumination,
    LightingEstimate,
    estimate_lighting,
    ground_view,
    illumination_from_strengths,
    solar_position,
)
from vc.calibration.materials import ground_albedo_prior, is_vegetation, luminance
from vc.errors import InputError
from vc.io import read_image
from vc.render.background import render_linear
from vc.render.layout_scene import layout_scene_dict
from vc.render.mitsuba_setup import mitsuba
from vc.render.sensor import ideal_view, perspective_sensor
from vc.scenes.layout import Box, Cylinder, Layout
from vc.scenes.loader import Scene
from vc.scenes.regions import Region
from vc.scenes.schema import Lighting, SolarLighting

#: Samples per pixel of the empty scene's re-render: the ground is uniform, so few are needed for medians.
RELIGHT_SPP = 8
#: Grey albedo of the re-render's ground; its shading is divided back out (mid-grey keeps interreflection real).
SHADING_ALBEDO = 0.5
#: White balance is fitted on the paved ground when at least this share of the known ground is paved.
MIN_PAVED_SHARE = 0.05
#: Segments of a cylinder's rings when its outline is cast as a shadow or projected.
CYLINDER_SEGMENTS = 16


def layout_solids(layout: Layout) -> list[np.ndarray]:
    """The vertices (N, 3) of every obstacle and wall: each is convex, so its hull is its shape."""
    solids = []
    for obstacle in layout.obstacles:
        if isinstance(obstacle, Box):
            solids.append(obstacle.corners())
        elif isinstance(obstacle, Cylinder):
            angles = np.linspace(0.0, 2.0 * np.pi, CYLINDER_SEGMENTS, endpoint=False)
            ring = np.c_[obstacle.base[0] + obstacle.radius * np.cos(angles),
                         obstacle.base[1] + obstacle.radius * np.sin(angles)]
            solids.append(np.concatenate([np.c_[ring, np.zeros(len(ring))],
                                          np.c_[ring, np.full(len(ring), obstacle.height)]]))
    for wall in layout.walls:
        direction = np.subtract(wall.end, wall.start)
        normal = np.array([-direction[1], direction[0]]) / np.linalg.norm(direction) * wall.thickness / 2
        base = np.array([np.add(wall.start, normal), np.add(wall.end, normal), np.subtract(wall.end, normal),
                         np.subtract(wall.start, normal)])
        solids.append(np.concatenate([np.c_[base, np.zeros(4)], np.c_[base, np.full(4, wall.height)]]))
    return solids


def explicit_illumination(lighting: Lighting) -> Illumination:
    return illumination_from_strengths(lighting.sun_azimuth_deg, lighting.sun_elevation_deg, lighting.sun_strength,
                                       lighting.sky_strength)


def known_sun(lighting: SolarLighting) -> tuple[float, float]:
    latitude, longitude = lighting.location
    return solar_position(latitude, longitude, lighting.time, lighting.north_deg)


@dataclass(frozen=True)
class RegionFit:
    """A region's known ground: median linear luminance of the background and of the re-render."""

    region: str
    pixels: int
    background: float
    rendered: float

    @property
    def error(self) -> float | None:
        """Re-render over background, minus one (None without known ground)."""
        return self.rendered / self.background - 1.0 if self.pixels and self.background > 0 else None

    def to_dict(self) -> dict:
        error = self.error
        return {"region": self.region, "pixels": self.pixels, "background": round(self.background, 5),
                "rendered": round(self.rendered, 5), "error": None if error is None else round(error, 4)}


@dataclass(frozen=True, eq=False)
class LightingFit:
    """The empty scene re-rendered under an illumination, against the background."""

    rendered: np.ndarray  # (H, W, 3) linear re-render, the known ground given its prior albedo
    known_ground: np.ndarray  # (H, W) bool
    vegetation: np.ndarray  # (H, W) bool: which of the background's pixels are vegetation
    background_luminance: np.ndarray  # (H, W) linear luminance of the background
    regions: list[RegionFit]
    gain: np.ndarray  # (3,) the exposure / white-balance gain that was applied to the estimate

    def log_error(self, window_px: int = 9) -> np.ndarray:
        """log2 of re-render over background luminance on known ground, each averaged over the known ground of a
        ``window_px`` square (the ground's texture and the re-render's sampling noise are not what is compared),
        NaN elsewhere (H, W)."""
        known = self.known_ground.astype(np.float32)
        kernel = (window_px, window_px)

        def local_mean(values: np.ndarray) -> np.ndarray:
            total = cv2.boxFilter(np.where(self.known_ground, values, 0.0).astype(np.float32), -1, kernel,
                                  normalize=False)
            return total / np.maximum(cv2.boxFilter(known, -1, kernel, normalize=False), 1e-6)

        with np.errstate(divide="ignore", invalid="ignore"):
            error = np.log2(local_mean(luminance(self.rendered)) / local_mean(self.background_luminance))
        return np.where(self.known_ground & np.isfinite(error), error, np.nan)

    @property
    def median_abs_error(self) -> float | None:
        errors = [abs(fit.error) for fit in self.regions if fit.error is not None]
        return float(np.median(errors)) if errors else None


@dataclass(frozen=True, eq=False)
class LightingSolution:
    """The light samples are rendered under, where it came from, and how well it explains the background."""

    illumination: Illumination
    source: str  # "scene file" or "estimated from the background"
    estimate: LightingEstimate | None
    fit: LightingFit | None

    def to_dict(self) -> dict:
        result = {"source": self.source, "illumination": self.illumination.to_dict()}
        if self.estimate is not None:
            estimate = self.estimate.to_dict()
            estimate.pop("illumination")
            result["estimate"] = estimate
        if self.fit is not None:
            result["exposure_gain"] = [round(float(g), 5) for g in self.fit.gain]
            result["regions"] = [fit.to_dict() for fit in self.fit.regions]
        return result

    def summary(self) -> str:
        light = self.illumination
        sky = f"sky {luminance(light.sky_rgb):.3f} ({light.sky_model})"
        sun = (f"sun {light.sun_to_sky:.2f}x sky at azimuth {light.sun_azimuth_deg:.0f}, elevation "
               f"{light.sun_elevation_deg:.0f} deg" if light.has_sun else "no direct sun")
        return f"{self.source}: {sky}, {sun}"


def background_view(scene: Scene, solids: list[np.ndarray]) -> GroundView:
    """The scene's background decoded with its response, and its known ground."""
    image = read_image(scene.image_path)
    response = scene.camera_response().response
    # Saturated highlights carry no level; a single channel at 0 is a saturated colour (a lawn's blue), not a
    # clipped pixel, and its luminance is still good.
    clipped = (image.max(axis=-1) == 255) | (image.max(axis=-1) == 0)
    return ground_view(scene.camera, response.decode(image), clipped, scene.layout.walkable_area(), solids)


def region_mask(camera: Camera, region: Region) -> np.ndarray:
    """The pixels of the image area a region owns (where its detections are kept)."""
    mask = np.zeros((camera.height, camera.width), np.uint8)
    for polygon in getattr(region.owned_image_area, "geoms", [region.owned_image_area]):
        if isinstance(polygon, shapely.Polygon) and not polygon.is_empty:
            points = np.round(np.asarray(polygon.exterior.coords) * 16).astype(np.int32)
            cv2.fillPoly(mask, [points], 1, cv2.LINE_8, 4)
    return mask.astype(bool)


def shading_render(scene: Scene, illumination: Illumination, spp: int = RELIGHT_SPP, seed: int = 0) -> np.ndarray:
    """The empty scene under ``illumination`` with a uniform :data:`SHADING_ALBEDO` ground, in the real camera's
    pixels (linear)."""
    view = ideal_view(scene.camera)
    scene_dict = layout_scene_dict(scene.layout, illumination, perspective_sensor(view.ideal, spp), seed=seed,
                                   ground_albedo=SHADING_ALBEDO)
    return view.warp(render_linear(mitsuba().load_dict(scene_dict), spp, seed))


def exposure_gain(background: np.ndarray, rendered: np.ndarray) -> np.ndarray:
    """The per-channel gain (N, 3 known-ground pixels) that brings the re-render to the background: its luminance
    is the median luminance ratio over all known ground (exposure); its colour the median channel ratios over the
    paved ground alone (white balance: grey-world on paving, whose prior is nearly neutral; a lawn's colour varies
    too much with the season and the light to balance a camera on), over all known ground where little is paved."""
    with np.errstate(divide="ignore", invalid="ignore"):
        exposure = np.median(luminance(background) / np.maximum(luminance(rendered), 1e-9))
        paved = ~is_vegetation(background)
        neutral = paved if paved.sum() >= MIN_PAVED_SHARE * len(background) else np.ones(len(background), bool)
        colour_ratios = background[neutral] / np.maximum(rendered[neutral], 1e-9)
    colour_gain = np.median(colour_ratios, axis=0) if len(colour_ratios) else np.ones(3)
    colour_gain = colour_gain / max(float(luminance(colour_gain)), 1e-9)
    return exposure * colour_gain if np.isfinite(exposure) and exposure > 0 else np.ones(3)


def fit_to_background(scene: Scene, illumination: Illumination, view: GroundView, regions: list[Region],
                      refine_gain: bool, spp: int = RELIGHT_SPP) -> tuple[Illumination, LightingFit]:
    """Re-render the empty scene under ``illumination``; with ``refine_gain`` fit the per-channel gain that
    matches the background on known ground and apply it. Returns the (scaled) illumination and the fit."""
    shading = shading_render(scene, illumination, spp)
    known = view.ground
    rendered = shading.astype(np.float64)
    prior = ground_albedo_prior(view.linear[known])
    rendered[known] = shading[known] / SHADING_ALBEDO * prior
    gain = exposure_gain(view.linear[known], rendered[known]) if refine_gain and known.any() else np.ones(3)
    rendered *= gain
    background_luminance, rendered_luminance = view.luminance, luminance(rendered)
    fits = []
    for region in regions:
        pixels = known & region_mask(scene.camera, region)
        count = int(pixels.sum())
        fits.append(RegionFit(region.name, count,
                              float(np.median(background_luminance[pixels])) if count else 0.0,
                              float(np.median(rendered_luminance[pixels])) if count else 0.0))
    return illumination.scaled(gain), LightingFit(rendered.astype(np.float32), known, is_vegetation(view.linear),
                                                  view.luminance, fits, gain)


def estimate_scene_lighting(scene: Scene, regions: list[Region], spp: int = RELIGHT_SPP) -> LightingSolution:
    """The light estimated from ``scene``'s background (whatever its ``lighting:`` says, except that a location
    and time fix the sun's direction), with its gain fitted against the re-rendered empty scene."""
    solids = layout_solids(scene.layout)
    view = background_view(scene, solids)
    sun = known_sun(scene.lighting) if isinstance(scene.lighting, SolarLighting) else None
    try:
        estimate = estimate_lighting(scene.camera, view, solids, known_sun=sun)
    except ValueError as error:
        raise InputError(scene.path, "lighting", f"cannot estimate the light: {error}") from None
    illumination, fit = fit_to_background(scene, estimate.illumination, view, regions, refine_gain=True, spp=spp)
    return LightingSolution(illumination, "estimated from the background", estimate, fit)


def solve_lighting(scene: Scene, regions: list[Region], spp: int = RELIGHT_SPP) -> LightingSolution:
    """The light ``scene``'s samples are rendered under: an explicit ``lighting:`` block as given (compared with
    the background, nothing fitted), otherwise :func:`estimate_scene_lighting`."""
    if not isinstance(scene.lighting, Lighting):
        return estimate_scene_lighting(scene, regions, spp)
    illumination = explicit_illumination(scene.lighting)
    view = background_view(scene, layout_solids(scene.layout))
    _, fit = fit_to_background(scene, illumination, view, regions, refine_gain=False, spp=spp)
    return LightingSolution(illumination, "scene file", None, fit)


def sun_angle_error_deg(a: Illumination, b: Illumination) -> float:
    """Angle between two illuminations' sun directions (degrees)."""
    cosine = float(np.clip(np.dot(a.towards_sun(), b.towards_sun()), -1.0, 1.0))
    return math.degrees(math.acos(cosine))


def write_comparison(scene: Scene, regions: list[Region], solution: LightingSolution, destination: Path) -> None:
    """``vc-scene light``'s figure: background, re-render, error map with the regions, per-region errors."""
    from vc.evaluation.plots import plot_lighting_comparison

    fit = solution.fit
    response = scene.camera_response().response
    outlines = {region.name: [np.asarray(polygon.exterior.coords)[:, :2]
                              for polygon in getattr(region.owned_image_area, "geoms", [region.owned_image_area])
                              if isinstance(polygon, shapely.Polygon) and not polygon.is_empty]
                for region in regions}
    median = fit.median_abs_error
    title = f"{scene.name} — {solution.summary()}" + (
        f"; median region error {median:.1%}" if median is not None else "")
    plot_lighting_comparison(read_image(scene.image_path), response.encode(fit.rendered), fit.log_error(),
                             outlines, {region.region: region.error for region in fit.regions}, destination, title)
