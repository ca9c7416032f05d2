"""Draw a scene's geometry over its background so that anyone can see at a glance whether it is right.

Everything is drawn through the real camera model (distortion included): walkable ground, obstacles and
walls as wireframes, region crop windows and owned areas, the horizon, and a grid of 1.75 m stick figures
standing on the walkable ground. If the calibration is wrong, the figures will not look like people standing
on that ground. A layout drawn in pixels (``frame: image``) is drawn as given too, thin white lines with a dot at
every given pixel, over its projection: where the two part, a pixel missed the ground it was meant to mark.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import shapely

from vc.calibration.camera import Camera
from vc.scenes.layout import densify_segments
from vc.scenes.loader import Scene
from vc.scenes.pixel_layout import PixelBox, PixelLayout
from vc.scenes.regions import Region, planning_domain, region_map

#: Region colours (RGB), cycled.
PALETTE = [(230, 25, 75), (60, 180, 75), (0, 130, 200), (245, 130, 48), (145, 30, 180), (70, 240, 240),
           (240, 50, 230), (210, 245, 60)]
OBSTACLE_COLOUR = (255, 60, 60)
WALL_COLOUR = (255, 170, 0)
WALKABLE_COLOUR = (80, 255, 120)
DRAWN_COLOUR = (255, 255, 255)
HORIZON_COLOUR = (255, 255, 0)
#: A 1.75 m stick figure in a local frame (x: the figure's right, z: up), metres. Head drawn separately.
FIGURE_BONES = np.array([
    [[-0.11, 0, 0.0], [-0.10, 0, 0.49]], [[-0.10, 0, 0.49], [-0.10, 0, 0.92]],
    [[0.11, 0, 0.0], [0.10, 0, 0.49]], [[0.10, 0, 0.49], [0.10, 0, 0.92]],
    [[-0.10, 0, 0.92], [0.10, 0, 0.92]], [[0.0, 0, 0.92], [0.0, 0, 1.45]],
    [[-0.19, 0, 1.43], [0.19, 0, 1.43]], [[-0.19, 0, 1.43], [-0.24, 0, 1.14]],
    [[-0.24, 0, 1.14], [-0.26, 0, 0.87]], [[0.19, 0, 1.43], [0.24, 0, 1.14]],
    [[0.24, 0, 1.14], [0.26, 0, 0.87]], [[0.0, 0, 1.45], [0.0, 0, 1.52]],
])
HEAD_CENTRE_Z, HEAD_RADIUS = 1.635, 0.115  # the top of the head at 1.75 m
FIGURE_COUNT = 40


def _to_pixels(uv: np.ndarray) -> np.ndarray:
    """Float pixels (centre convention) -> cv2 fixed-point coordinates with 4 fractional bits."""
    return np.round(uv * 16).astype(np.int32)


def image_runs(camera: Camera, points: np.ndarray, closed: bool = False) -> list[np.ndarray]:
    """The (N, 2) pixel runs of the projected polyline through 3-D ``points``, broken wherever a point cannot be
    imaged (behind the camera, or thrown to infinity by the distortion)."""
    projection = camera.project(points)
    uv, ok = projection.uv, projection.ok
    if closed:
        uv, ok = np.vstack([uv, uv[:1]]), np.append(ok, ok[0])
    runs, current = [], []
    for point, good in zip(uv, ok, strict=True):
        if good and np.all(np.abs(point) < 1e5):
            current.append(point)
        elif current:
            runs.append(current)
            current = []
    if current:
        runs.append(current)
    return [np.array(run) for run in runs if len(run) >= 2]


def draw_polyline(image: np.ndarray, camera: Camera, points: np.ndarray, colour, thickness: int = 1,
                  closed: bool = False) -> None:
    """Project 3-D points and draw the polyline, broken wherever a point cannot be imaged."""
    for run in image_runs(camera, points, closed):
        cv2.polylines(image, [_to_pixels(run)], False, colour, thickness, cv2.LINE_AA, shift=4)


def _draw_segments(image: np.ndarray, camera: Camera, segments: np.ndarray, colour, thickness: int = 1) -> None:
    for line in densify_segments(segments):
        draw_polyline(image, camera, line, colour, thickness)


def _ground_rings(geometry: shapely.Geometry) -> list[np.ndarray]:
    polygons = [geometry] if isinstance(geometry, shapely.Polygon) else list(getattr(geometry, "geoms", []))
    rings = []
    for polygon in polygons:
        if polygon.is_empty:
            continue
        for ring in (polygon.exterior, *polygon.interiors):
            xy = np.asarray(ring.segmentize(0.1).coords)[:, :2]
            rings.append(np.c_[xy, np.zeros(len(xy))])
    return rings


def _figure_positions(domain: shapely.Geometry, count: int) -> np.ndarray:
    """About ``count`` feet positions on a square grid inside ``domain``."""
    step = math.sqrt(domain.area / count)
    x0, y0, x1, y1 = domain.bounds
    gx, gy = np.meshgrid(np.arange(x0 + step / 2, x1, step), np.arange(y0 + step / 2, y1, step))
    inside = shapely.contains_xy(domain, gx.ravel(), gy.ravel())
    return np.c_[gx.ravel()[inside], gy.ravel()[inside], np.zeros(inside.sum())]


def figure_lines(camera: Camera, foot: np.ndarray, height_m: float = 1.75) -> list[np.ndarray]:
    """The 3-D polylines of a stick figure of ``height_m`` standing at ``foot``, turned to face the camera: its bones
    (densified, so that a distorting lens bends them as it would) and its head."""
    to_camera = camera.center[:2] - foot[:2]
    facing = to_camera / max(np.linalg.norm(to_camera), 1e-9)
    right = np.array([facing[1], -facing[0], 0.0])
    towards = np.array([facing[0], facing[1], 0.0])
    scale = height_m / 1.75

    def world(local: np.ndarray) -> np.ndarray:
        return foot + scale * (local[..., :1] * right + local[..., 1:2] * towards + local[..., 2:3] * [0, 0, 1])

    a = np.linspace(0, 2 * np.pi, 25)
    head = np.c_[HEAD_RADIUS * np.cos(a), np.zeros_like(a), HEAD_CENTRE_Z + HEAD_RADIUS * np.sin(a)]
    return [*densify_segments(world(FIGURE_BONES)), world(head)]


def draw_figure(image: np.ndarray, camera: Camera, foot: np.ndarray, colour, height_m: float = 1.75) -> None:
    """A stick figure of ``height_m`` standing at ``foot``, turned to face the camera."""
    for line in figure_lines(camera, foot, height_m):
        draw_polyline(image, camera, line, colour, 1)


def draw_label(image: np.ndarray, text: str, origin: tuple[int, int], colour) -> None:
    x, y = origin
    (w, h), base = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.45, 1)
    y = max(y, h + 2)
    cv2.rectangle(image, (x, y - h - 3), (x + w + 4, y + base - 1), (0, 0, 0), -1)
    cv2.putText(image, text, (x + 2, y - 1), cv2.FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv2.LINE_AA)


def draw_horizon(image: np.ndarray, camera: Camera) -> None:
    """The camera's horizon, yellow, where it crosses the image."""
    horizon = camera.horizon_pixels()
    horizon = horizon[camera.is_in_image(horizon, margin=max(camera.size))]
    if len(horizon) >= 2 and camera.is_in_image(horizon).any():
        cv2.polylines(image, [_to_pixels(horizon)], False, HORIZON_COLOUR, 1, cv2.LINE_AA, shift=4)


def draw_pixel_input(image: np.ndarray, drawn: PixelLayout) -> None:
    """The layout as drawn in pixels: walkable outlines, box footprints, cylinder bases and wall lines."""
    def outline(points: list[list[float]], closed: bool) -> None:
        uv = np.asarray(points, np.float64)
        cv2.polylines(image, [_to_pixels(uv)], closed, DRAWN_COLOUR, 1, cv2.LINE_AA, shift=4)
        for point in _to_pixels(uv):
            cv2.circle(image, tuple(int(v) for v in point), 3 * 16, DRAWN_COLOUR, -1, cv2.LINE_AA, shift=4)

    for polygon in drawn.walkable:
        outline(polygon, closed=True)
    for obstacle in drawn.obstacles:
        outline(obstacle.footprint if isinstance(obstacle, PixelBox) else [obstacle.base], closed=True)
    for wall in drawn.walls:
        outline([wall.start, wall.end], closed=False)


def draw_overlay(scene: Scene, background: np.ndarray, regions: list[Region]) -> np.ndarray:
    """The background (H, W, 3 uint8, RGB) with the scene's geometry drawn on it."""
    camera = scene.camera
    image = background.copy()
    owner = region_map(camera, regions)
    tint = np.zeros_like(image, dtype=np.float32)
    for index in range(len(regions)):
        tint[owner == index] = PALETTE[index % len(PALETTE)]
    owned = (owner >= 0)[..., None]
    image = np.where(owned, 0.78 * image + 0.22 * tint, image).astype(np.uint8)
    for ring in _ground_rings(planning_domain(scene, scene.regions)):
        draw_polyline(image, camera, ring, WALKABLE_COLOUR, 2, closed=True)
    for blocker in scene.layout.blockers():
        colour = WALL_COLOUR if blocker in scene.layout.walls else OBSTACLE_COLOUR
        _draw_segments(image, camera, blocker.edges(), colour, 1)
    if scene.drawn_layout is not None:
        draw_pixel_input(image, scene.drawn_layout)
    draw_horizon(image, camera)
    for index, region in enumerate(regions):
        colour = PALETTE[index % len(PALETTE)]
        for foot in _figure_positions(region.ground, max(4, FIGURE_COUNT // len(regions))):
            draw_figure(image, camera, foot, colour)
    for index, region in enumerate(regions):
        colour = PALETTE[index % len(PALETTE)]
        crop = region.crop
        inset = 2 * index  # keep windows that share an image edge apart
        cv2.rectangle(image, (crop.x0 + inset, crop.y0 + inset), (crop.x1 - 1 - inset, crop.y1 - 1 - inset),
                      colour, 2)
        draw_label(image, f"{region.name}  {crop.width}x{crop.height} -> {region.input_size[0]}x"
                      f"{region.input_size[1]}  people {region.person_px[0]:.0f}-{region.person_px[1]:.0f} px",
               (crop.x0 + inset + 2, crop.y0 + inset + 16), colour)
    return image
