"""A layout drawn on the background image: what an installer without a site plan has.

``layout: {frame: image, ...}`` gives the walkable polygons, obstacle footprints and wall lines in pixels of the
background (OpenCV convention), and heights, radii and thicknesses in metres. The loader projects every pixel
onto the ground through the scene's calibration (:meth:`PixelLayout.to_ground`) and from then on the scene has an
ordinary metric :class:`vc.scenes.layout.Layout`; the pixel input is kept for ``vc-scene show`` to draw beside
the projection.

* ``walkable``: polygons of ``[u, v]`` pixels on the ground;
* ``obstacles``: a ``cylinder`` by the pixel of the centre of its base (``base``), with ``radius`` and ``height``
  in metres; a ``box`` by the pixels of its footprint on the ground (``footprint``, three or more points: the
  smallest rectangle around their ground positions is the box) with its ``height`` and, for a box that does not
  stand on the ground (a sign), the height of its ``bottom``;
* ``walls``: the pixels of the two ends of the wall's foot line (``start``, ``end``), ``height`` and
  ``thickness`` in metres.

A pixel whose ray does not meet the ground (above the horizon) cannot be placed and is refused, naming it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import numpy as np
import shapely
from pydantic import Discriminator, Field, Tag, ValidationError

from vc.calibration.camera import Camera
from vc.errors import InputError
from vc.scenes.layout import Layout, StrictModel, Vec2

#: A box footprint narrower than this on the ground (m) is a line, not a footprint.
MIN_FOOTPRINT_SIDE_M = 0.02


class PixelCylinder(StrictModel):
    type: Literal["cylinder"]
    base: Vec2  # px
    radius: float = Field(gt=0)  # m
    height: float = Field(gt=0)  # m
    name: str | None = None


class PixelBox(StrictModel):
    type: Literal["box"]
    footprint: Annotated[list[Vec2], Field(min_length=3)]  # px, on the ground
    height: float = Field(gt=0)  # m
    bottom: float = Field(0.0, ge=0)  # m above the ground
    name: str | None = None


class PixelWall(StrictModel):
    start: Vec2  # px, where the wall meets the ground
    end: Vec2
    height: float = Field(gt=0)
    thickness: float = Field(0.2, gt=0)
    name: str | None = None


PixelObstacle = Annotated[Annotated[PixelBox, Tag("box")] | Annotated[PixelCylinder, Tag("cylinder")],
                          Discriminator(lambda value: value.get("type") if isinstance(value, dict)
                                        else getattr(value, "type", None))]


class PixelLayout(StrictModel):
    """A :class:`vc.scenes.layout.Layout` in pixels of the background (see the module docstring)."""

    frame: Literal["image"]
    walkable: Annotated[list[Annotated[list[Vec2], Field(min_length=3)]], Field(min_length=1)]
    obstacles: list[PixelObstacle] = []
    walls: list[PixelWall] = []

    def to_ground(self, camera: Camera, path: Path | None = None) -> Layout:
        """The metric layout these pixels show, through ``camera``; InputError naming the first pixel that sees
        no ground, or a projected shape that is not valid."""
        walkable = [ground_points(camera, polygon, f"layout.walkable.{index}", path).round(4).tolist()
                    for index, polygon in enumerate(self.walkable)]
        obstacles = [obstacle_on_ground(obstacle, camera, f"layout.obstacles.{index}", path)
                     for index, obstacle in enumerate(self.obstacles)]
        walls = [wall_on_ground(wall, camera, f"layout.walls.{index}", path) for index, wall in enumerate(self.walls)]
        try:
            return Layout(walkable=walkable, obstacles=obstacles, walls=walls)
        except ValidationError as error:
            first = error.errors(include_url=False)[0]
            location = ".".join(str(part) for part in first["loc"] if part not in ("box", "cylinder"))
            raise InputError(path, f"layout.{location}", "projected onto the ground: "
                             + first["msg"].removeprefix("Value error, ")) from None


def ground_points(camera: Camera, pixels: list[list[float]], field: str, path: Path | None = None) -> np.ndarray:
    """(N, 2) ground metres the background's ``pixels`` see; InputError naming the first pixel above the horizon."""
    hit = camera.ground_from_pixels(np.asarray(pixels, np.float64).reshape(-1, 2))
    if not hit.ok.all():
        index = int(np.argmin(hit.ok))
        u, v = pixels[index]
        where = field if len(pixels) == 1 else f"{field}.{index}"
        raise InputError(path, where, f"pixel ({u:g}, {v:g}) is above the horizon: its ray never meets the ground")
    return hit.points[:, :2]


def obstacle_on_ground(obstacle: PixelBox | PixelCylinder, camera: Camera, field: str,
                       path: Path | None = None) -> dict:
    """A drawn obstacle as its metric :mod:`vc.scenes.layout` entry."""
    if isinstance(obstacle, PixelCylinder):
        base = ground_points(camera, [obstacle.base], f"{field}.base", path)[0]
        return {"type": "cylinder", "name": obstacle.name, "base": base.round(4).tolist(), "radius": obstacle.radius,
                "height": obstacle.height}
    return _box(ground_points(camera, obstacle.footprint, f"{field}.footprint", path), obstacle, field, path)


def wall_on_ground(wall: PixelWall, camera: Camera, field: str, path: Path | None = None) -> dict:
    """A drawn wall as its metric :class:`vc.scenes.layout.Wall` entry."""
    start, end = (ground_points(camera, [point], f"{field}.{key}", path)[0]
                  for key, point in (("start", wall.start), ("end", wall.end)))
    return {"name": wall.name, "start": start.round(4).tolist(), "end": end.round(4).tolist(), "height": wall.height,
            "thickness": wall.thickness}


def _box(footprint: np.ndarray, box: PixelBox, field: str, path: Path | None) -> dict:
    """The smallest rectangle around the footprint's ground points, as a :class:`vc.scenes.layout.Box`."""
    rectangle = shapely.minimum_rotated_rectangle(shapely.MultiPoint(footprint))
    corners = np.asarray(rectangle.exterior.coords)[:4] if isinstance(rectangle, shapely.Polygon) else None
    sides = np.diff(np.vstack([corners, corners[:1]]), axis=0)[:2] if corners is not None else np.zeros((2, 2))
    length, width = np.linalg.norm(sides, axis=1)
    if min(length, width) < MIN_FOOTPRINT_SIDE_M:
        raise InputError(path, f"{field}.footprint", "its points are (nearly) collinear on the ground: a footprint "
                                                     "needs area")
    yaw = float(np.degrees(np.arctan2(sides[0, 1], sides[0, 0])))
    centre = corners.mean(axis=0)
    return {"type": "box", "name": box.name, "center": [*centre.round(4).tolist(), box.bottom + box.height / 2],
            "size": [float(length), float(width), box.height], "yaw": round(yaw, 4)}
