"""Region planning: split the visible walkable ground into regions, each with its own network.

A region (docs/design.md "Regions") has a ground polygon, an image crop window containing every person of the
allowed heights standing anywhere in that polygon (plus margin), a network input size (the crop resized so
that people come out at ``target_person_px``, or at the region's own size in ``person_px_by_region``), and the
image area it owns (where its polygon's foot points land). ``auto`` cuts the ground into depth bands inside
which the pixel height of a reference person varies by at most ``max_height_ratio``; ``single`` is the paper's
SPN-G; ``explicit`` takes the polygons as given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import contourpy
import numpy as np
import shapely
from shapely.geometry import Polygon

from vc.calibration.camera import Camera
from vc.errors import InputError
from vc.scenes.loader import Scene
from vc.scenes.schema import RegionPlanSpec

#: Ground sampling step for planning, relative to the size of the visible walkable area.
GRID_CELLS = 320
#: Radius (m) of the cylinder a person is taken to occupy when sizing crop windows.
PERSON_RADIUS_M = 0.35
#: Pieces of ground smaller than this (m^2) are slivers of grid interpolation, not regions.
MIN_REGION_AREA_M2 = 0.05
#: The tallest person a region plans for, as a fraction of the image height: beyond it no crop holds them.
MAX_PERSON_FRACTION = 1.0


@dataclass(frozen=True)
class CropWindow:
    """An axis-aligned window of whole pixels: pixel (x0, y0) is its top-left pixel."""

    x0: int
    y0: int
    width: int
    height: int

    @property
    def x1(self) -> int:
        return self.x0 + self.width

    @property
    def y1(self) -> int:
        return self.y0 + self.height

    def to_list(self) -> list[int]:
        return [self.x0, self.y0, self.width, self.height]


@dataclass(frozen=True)
class Region:
    name: str
    ground: shapely.Geometry
    crop: CropWindow
    input_size: tuple[int, int]
    person_px: tuple[float, float]
    reference_px: tuple[float, float]
    owned_image_area: shapely.Geometry

    def camera(self, scene_camera: Camera) -> Camera:
        """The camera of this region's network input: the scene camera cropped, then resized."""
        crop = self.crop
        return scene_camera.cropped(crop.x0, crop.y0, crop.width, crop.height).resized(*self.input_size)

    @property
    def scale(self) -> tuple[float, float]:
        return (self.input_size[0] / self.crop.width, self.input_size[1] / self.crop.height)

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            # Outlines simplified for reading: 1 cm on the ground, a quarter pixel in the image.
            "ground_polygon": shapely.geometry.mapping(shapely.set_precision(self.ground.simplify(0.01), 0.001)),
            "ground_area_m2": round(float(self.ground.area), 3),
            "crop_window": self.crop.to_list(),
            "input_size": list(self.input_size),
            "scale": [round(s, 6) for s in self.scale],
            "person_height_px": [round(v, 2) for v in self.person_px],
            "reference_height_px": [round(v, 2) for v in self.reference_px],
            "owned_image_area": shapely.geometry.mapping(
                shapely.set_precision(self.owned_image_area.simplify(0.25), 0.01)),
        }


def max_visible_distance(camera: Camera, person_height_m: float, min_person_px: float) -> float:
    """Ground distance beyond which a ``person_height_m`` person is shorter than ``min_person_px`` (pinhole)."""
    return max(camera.fx, camera.fy) * person_height_m / min_person_px


def visible_ground(camera: Camera, max_distance: float, border_step_px: float = 2.0) -> shapely.Geometry:
    """The ground (z = 0) seen through the image, no farther than ``max_distance`` from the camera's foot.

    The image border is walked pixel by pixel and each ray is met with the ground; rays above the horizon or
    beyond ``max_distance`` are replaced by the ground point at ``max_distance`` in the same compass
    direction. The resulting fan is cut by the disc of radius ``max_distance``.
    """
    w, h = camera.width, camera.height
    xs = np.linspace(-0.5, w - 0.5, int(w / border_step_px) + 1)
    ys = np.linspace(-0.5, h - 0.5, int(h / border_step_px) + 1)
    border = np.concatenate([  # clockwise: top, right, bottom, left
        np.c_[xs, np.full_like(xs, -0.5)], np.c_[np.full_like(ys, w - 0.5), ys],
        np.c_[xs[::-1], np.full_like(xs, h - 0.5)], np.c_[np.full_like(ys, -0.5), ys[::-1]],
    ])
    rays, ray_ok = camera.unproject(border)
    hits = camera.ground_from_pixels(border)
    foot = camera.center.copy()
    foot[2] = 0.0
    azimuth = rays[:, :2] / np.maximum(np.linalg.norm(rays[:, :2], axis=1, keepdims=True), 1e-12)
    far = foot[:2] + max_distance * azimuth
    distance = np.linalg.norm(hits.points[:, :2] - foot[:2], axis=1)
    use_hit = hits.ok & (distance <= max_distance)
    outline = np.where(use_hit[:, None], hits.points[:, :2], far)[ray_ok]
    if len(outline) < 3:
        return Polygon()
    fan = shapely.make_valid(Polygon(outline))
    disc = shapely.Point(foot[:2]).buffer(max_distance, quad_segs=64)
    return fan.intersection(disc)


def ground_where_people_fit(camera: Camera, domain: shapely.Geometry, tallest_m: float) -> shapely.Geometry:
    """The part of ``domain`` where the tallest person projects whole (head in front of the camera, inside the
    lens model's domain) and no taller than the image (:data:`MAX_PERSON_FRACTION`).

    Next to a low, wide camera a person's head can reach the camera's own height or its image plane, where the
    pixel height grows without bound: no crop can hold such a person and no height band can be drawn there."""
    x0, y0, x1, y1 = domain.bounds
    step = max(x1 - x0, y1 - y0) / GRID_CELLS
    xs, ys = np.arange(x0 - step, x1 + 2 * step, step), np.arange(y0 - step, y1 + 2 * step, step)
    gx, gy = np.meshgrid(xs, ys)
    heights = camera.person_pixel_height(np.stack([gx, gy, np.zeros_like(gx)], axis=-1), tallest_m)
    limit = MAX_PERSON_FRACTION * camera.height
    if np.nanmax(heights, initial=0.0) <= limit and np.isfinite(heights).all():
        return domain  # the usual case: everyone fits everywhere
    fits = np.where(np.isfinite(heights) & (heights <= limit), 1.0, 0.0)
    generator = contourpy.contour_generator(gx, gy, fits, fill_type=contourpy.FillType.OuterOffset)
    return _without_slivers(domain.intersection(_filled(generator, 0.5, 1.5)))


def planning_domain(scene: Scene, spec: RegionPlanSpec) -> shapely.Geometry:
    """Walkable, standable ground that the camera sees with people at least ``min_person_px`` tall and, for
    the tallest, whole and no taller than the image."""
    low_height, tallest = scene.priors.height_m
    reach = max_visible_distance(scene.camera, low_height, spec.min_person_px)
    domain = scene.layout.standable_area().intersection(visible_ground(scene.camera, reach))
    domain = _without_slivers(domain)
    if domain.is_empty:
        raise InputError(scene.path, "layout.walkable", "no walkable area is in view of the camera (within "
                                                        f"{reach:.0f} m, where people are >= "
                                                        f"{spec.min_person_px:g} px tall)")
    domain = ground_where_people_fit(scene.camera, domain, tallest)
    if domain.is_empty:
        raise InputError(scene.path, "camera", f"everywhere in view, a {tallest:g} m person is taller than the "
                                               f"image or cannot be seen whole (the camera is too close to the "
                                               f"walkable area, or too low beside it)")
    return domain


def _polygons(geometry: shapely.Geometry) -> list[Polygon]:
    if geometry.is_empty:
        return []
    if isinstance(geometry, Polygon):
        return [geometry]
    return [g for part in getattr(geometry, "geoms", []) for g in _polygons(part)]


def _without_slivers(geometry: shapely.Geometry) -> shapely.Geometry:
    parts = [p for p in _polygons(geometry) if p.area >= MIN_REGION_AREA_M2]
    return shapely.union_all(parts) if parts else Polygon()


def sample_ground(geometry: shapely.Geometry, step: float) -> np.ndarray:
    """Points (N, 3) on z = 0 covering ``geometry``: a grid of ``step`` inside plus its densified outline."""
    x0, y0, x1, y1 = geometry.bounds
    xs = np.arange(x0, x1 + step, step)
    ys = np.arange(y0, y1 + step, step)
    gx, gy = np.meshgrid(xs, ys)
    inside = shapely.contains_xy(geometry, gx.ravel(), gy.ravel())
    interior = np.c_[gx.ravel()[inside], gy.ravel()[inside]]
    outline = [np.asarray(ring.segmentize(step / 2).coords)[:, :2]
               for polygon in _polygons(geometry) for ring in (polygon.exterior, *polygon.interiors)]
    points = np.concatenate([interior, *outline]) if outline else interior
    return np.c_[points, np.zeros(len(points))]


def _height_bands(camera: Camera, domain: shapely.Geometry, spec: RegionPlanSpec) -> list[shapely.Geometry]:
    """Cut ``domain`` along iso-lines of the reference person's pixel height into equal-ratio bands."""
    x0, y0, x1, y1 = domain.bounds
    step = max(x1 - x0, y1 - y0) / GRID_CELLS
    xs, ys = np.arange(x0 - step, x1 + 2 * step, step), np.arange(y0 - step, y1 + 2 * step, step)
    gx, gy = np.meshgrid(xs, ys)
    feet = np.stack([gx, gy, np.zeros_like(gx)], axis=-1)
    heights = camera.person_pixel_height(feet, spec.reference_height_m)
    samples = _seen_heights(camera, sample_ground(domain, step), spec.reference_height_m)
    samples = samples[np.isfinite(samples)]
    low, high = float(samples.min()), float(samples.max())
    bands = max(1, math.ceil(math.log(high / low) / math.log(spec.max_height_ratio) - 1e-9))
    if bands == 1:
        return [domain]
    levels = low * (high / low) ** (np.arange(bands + 1) / bands)
    levels[0], levels[-1] = 0.0, np.inf  # keep every grid-interpolated sliver at the extremes
    generator = contourpy.contour_generator(gx, gy, np.ma.masked_invalid(np.log(heights)),
                                            fill_type=contourpy.FillType.OuterOffset)
    pieces = [_without_slivers(_filled(generator, np.log(max(lower, 1e-300)), np.log(min(upper, 1e300)))
                               .intersection(domain)) for lower, upper in zip(levels[:-1], levels[1:], strict=True)]
    # A domain barely larger than a sliver can fall apart into bands that are each smaller than one: it stays one
    # region (found by the planning property: a fisheye seeing 0.06 m2 of ground planned none).
    return [p for p in pieces if not p.is_empty] or [domain]


def _filled(generator: contourpy.ContourGenerator, lower: float, upper: float) -> shapely.Geometry:
    """The ground where the generator's field lies between ``lower`` and ``upper``, as one geometry."""
    polygons, offsets = generator.filled(lower, upper)
    rings = [Polygon(points[offset[0]:]) if len(offset) == 1 else
             Polygon(points[offset[0]:offset[1]], [points[a:b] for a, b in zip(offset[1:-1], offset[2:], strict=True)])
             for points, offset in zip(polygons, offsets, strict=True)]
    return shapely.union_all([shapely.make_valid(ring) for ring in rings]) if rings else Polygon()


def crop_window(camera: Camera, ground: shapely.Geometry, tallest_m: float, margin_px: int,
                step: float) -> CropWindow:
    """Smallest pixel window (clipped to the image) holding anyone up to ``tallest_m`` standing on ``ground``."""
    feet = sample_ground(ground, step)
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = np.c_[np.cos(angles), np.sin(angles), np.zeros(8)] * PERSON_RADIUS_M
    body = np.concatenate([ring, ring + [0, 0, tallest_m]])
    projected = camera.project((feet[:, None, :] + body[None]).reshape(-1, 3))
    # Clipped to just outside the image first: the window is clipped to it anyway, and a strong lens can cast a
    # head to a finite 1e20 px that no integer holds (found by the planning property).
    uv = np.clip(projected.uv[projected.ok], -1.0, [camera.width, camera.height])
    left, top = np.floor(uv.min(axis=0) - margin_px).astype(int)
    right, bottom = np.ceil(uv.max(axis=0) + margin_px).astype(int)
    left, top = max(left, 0), max(top, 0)
    right, bottom = min(right, camera.width - 1), min(bottom, camera.height - 1)
    return CropWindow(int(left), int(top), int(right - left + 1), int(bottom - top + 1))


def owned_image_area(camera: Camera, ground: shapely.Geometry, step: float = 0.05) -> shapely.Geometry:
    """The image area (pixels, clipped to the image) where feet standing on ``ground`` are seen.

    The ground polygons come from the visible fan, so every vertex projects; outlines are densified so that
    lens distortion bends the edges as it bends the image.
    """
    def to_pixels(ring) -> np.ndarray:
        xy = np.asarray(ring.segmentize(step).coords)[:, :2]
        return camera.project(np.c_[xy, np.zeros(len(xy))]).uv

    pieces = [Polygon(to_pixels(p.exterior), [to_pixels(r) for r in p.interiors]) for p in _polygons(ground)]
    image = shapely.box(-0.5, -0.5, camera.width - 0.5, camera.height - 0.5)
    return shapely.union_all([shapely.make_valid(p) for p in pieces]).intersection(image)


def _round_to_multiple(value: float, multiple: int) -> int:
    return max(multiple, int(round(value / multiple)) * multiple)


def _seen_heights(camera: Camera, feet: np.ndarray, height_m: float) -> np.ndarray:
    """Pixel heights of people standing at ``feet``, NaN where unseen or where head and feet meet in one pixel
    (straight below the camera: a top-down view sees a head, not a height; found by the planning property, where
    a foot sample at the nadir made a zero height and a division by it)."""
    heights = camera.person_pixel_height(feet, height_m)
    return np.where(heights > 0, heights, np.nan)


def _make_region(name: str, camera: Camera, ground: shapely.Geometry, spec: RegionPlanSpec,
                 height_range: tuple[float, float], step: float) -> Region:
    feet = sample_ground(ground, step)
    reference = _seen_heights(camera, feet, spec.reference_height_m)
    low = _seen_heights(camera, feet, height_range[0])
    high = _seen_heights(camera, feet, height_range[1])
    reference_px = (float(np.nanmin(reference)), float(np.nanmax(reference)))
    person_px = (float(np.nanmin(low)), float(np.nanmax(high)))
    crop = crop_window(camera, ground, height_range[1], spec.margin_px, step)
    # People come out at their target size for the band's geometric-mean size; never upscale beyond max_upscale.
    target_px = spec.person_px_by_region.get(name, spec.target_person_px)
    scale = min(target_px / math.sqrt(reference_px[0] * reference_px[1]), spec.max_upscale)
    input_size = (_round_to_multiple(crop.width * scale, spec.input_multiple),
                  _round_to_multiple(crop.height * scale, spec.input_multiple))
    return Region(name, ground, crop, input_size, person_px, reference_px, owned_image_area(camera, ground))


def plan_regions(scene: Scene) -> list[Region]:
    """The scene's regions, ordered from far (small people) to near."""
    spec = scene.regions
    camera = scene.camera
    domain = planning_domain(scene, spec)
    x0, y0, x1, y1 = domain.bounds
    step = max(x1 - x0, y1 - y0) / GRID_CELLS
    if spec.mode == "explicit":
        grounds = []
        for index, named in enumerate(spec.polygons):
            ground = _without_slivers(Polygon(named.polygon).intersection(domain))
            if ground.is_empty:
                raise InputError(scene.path, f"regions.polygons.{index}", f"region {named.name!r} covers no "
                                                                         "visible walkable ground")
            for other_index, (other_name, other) in enumerate(grounds):
                if ground.intersection(other).area > MIN_REGION_AREA_M2:
                    raise InputError(scene.path, f"regions.polygons.{index}",
                                     f"region {named.name!r} overlaps region {other_name!r} "
                                     f"(regions.polygons.{other_index}); ownership would be ambiguous")
            grounds.append((named.name, ground))
    elif spec.mode == "single":
        grounds = [("all", domain)]
    else:
        bands = _height_bands(camera, domain, spec)
        grounds = [(f"r{index}", band) for index, band in enumerate(bands)]
    unknown = sorted(set(spec.person_px_by_region) - {name for name, _ in grounds})
    if unknown:
        raise InputError(scene.path, f"regions.person_px_by_region.{unknown[0]}",
                         f"the plan has no region {unknown[0]!r} (it has {', '.join(name for name, _ in grounds)})")
    regions = [_make_region(name, camera, ground, spec, tuple(scene.priors.height_m), step)
               for name, ground in grounds]
    return sorted(regions, key=lambda r: r.reference_px[0]) if spec.mode == "auto" else regions


def region_map(camera: Camera, regions: list[Region]) -> np.ndarray:
    """(H, W) int16 image: the index of the region owning a foot point at each pixel, -1 for none."""
    v, u = np.mgrid[0:camera.height, 0:camera.width].astype(np.float64)
    hits = camera.ground_from_pixels(np.stack([u, v], axis=-1).reshape(-1, 2))
    owner = np.full(hits.ok.shape, -1, dtype=np.int16)
    x, y = hits.points[:, 0], hits.points[:, 1]
    for index, region in enumerate(regions):
        inside = hits.ok & (owner < 0)
        inside[inside] = shapely.contains_xy(region.ground, x[inside], y[inside])
        owner[inside] = index
    return owner.reshape(camera.height, camera.width)
