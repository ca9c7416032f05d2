"""Layout geometry of a scene: walkable ground polygons, box and cylinder obstacles, walls.

The classes are the validated YAML fields (pydantic) and carry the geometry that the region planner, the
overlay and the renderer need: ground footprints (shapely, metres) and 3-D edges for wireframes.
World convention: metres, z up, ground plane z = 0.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
import shapely
from pydantic import AfterValidator, BaseModel, ConfigDict, Field, field_validator, model_validator
from shapely.geometry import LineString, Polygon
from shapely.validation import explain_validity


def _finite(values: list[float]) -> list[float]:
    if not np.isfinite(np.asarray(values, dtype=np.float64)).all():
        raise ValueError("must be finite numbers")
    return values


Vec2 = Annotated[list[float], Field(min_length=2, max_length=2), AfterValidator(_finite)]
Vec3 = Annotated[list[float], Field(min_length=3, max_length=3), AfterValidator(_finite)]
PositiveVec3 = Annotated[list[Annotated[float, Field(gt=0)]], Field(min_length=3, max_length=3)]

#: Segments are cut into this many pieces so that lens distortion bends them visibly in overlays.
EDGE_PIECES = 16
#: Obstacles whose bottom is within this height of the ground block standing there (a sign on a pole doesn't).
GROUND_CONTACT_M = 0.3


class StrictModel(BaseModel):
    """Unknown fields are errors: a typo in a scene file must not pass silently."""

    model_config = ConfigDict(extra="forbid", frozen=True)


def validate_ground_polygon(points: list[list[float]]) -> Polygon:
    """A simple polygon with positive area from [[x, y], ...] metres, or ValueError saying what is wrong."""
    if len(points) < 3:
        raise ValueError(f"a polygon needs at least 3 points, got {len(points)}")
    if not np.isfinite(np.asarray(points, dtype=np.float64)).all():
        raise ValueError("polygon coordinates must be finite numbers")
    polygon = Polygon(points)
    if not polygon.is_valid:
        raise ValueError(f"polygon is not simple ({explain_validity(polygon)})")
    if polygon.area <= 1e-6:
        raise ValueError("polygon has zero area")
    return polygon


class _StandsOnGround(StrictModel):
    """A shape rising from the ground to its ``height``, a field each subclass declares in its own place (a field
    here would come first in every scene's dump, and so change the scenes' hashes)."""

    @property
    def bottom(self) -> float:
        return 0.0

    @property
    def top(self) -> float:
        return self.height


class Box(StrictModel):
    """An axis-aligned box rotated by ``yaw`` degrees about z; ``center`` is its 3-D centre."""

    type: Literal["box"]
    center: Vec3
    size: PositiveVec3
    yaw: float = 0.0
    name: str | None = None

    @model_validator(mode="after")
    def _above_ground(self) -> Box:
        if self.center[2] - self.size[2] / 2 < -0.05:
            raise ValueError("box reaches below the ground (center z - size z / 2 < 0)")
        return self

    @property
    def bottom(self) -> float:
        return self.center[2] - self.size[2] / 2

    @property
    def top(self) -> float:
        return self.center[2] + self.size[2] / 2

    def corners(self) -> np.ndarray:
        """The 8 corners (8, 3): bottom four counter-clockwise, then the top four."""
        hx, hy, hz = (s / 2 for s in self.size)
        local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
        a = np.radians(self.yaw)
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        xy = local @ rot.T + np.asarray(self.center[:2])
        z0, z1 = self.center[2] - hz, self.center[2] + hz
        return np.concatenate([np.c_[xy, np.full(4, z0)], np.c_[xy, np.full(4, z1)]])

    def footprint(self) -> Polygon:
        return Polygon(self.corners()[:4, :2])

    def edges(self) -> np.ndarray:
        c = self.corners()
        pairs = [(i, (i + 1) % 4) for i in range(4)] + [(i + 4, (i + 1) % 4 + 4) for i in range(4)]
        pairs += [(i, i + 4) for i in range(4)]
        return np.array([[c[a], c[b]] for a, b in pairs])


class Cylinder(_StandsOnGround):
    """A vertical cylinder standing on the ground at ``base`` (a lamp post, a bollard, a tree trunk)."""

    type: Literal["cylinder"]
    base: Vec2
    radius: float = Field(gt=0)
    height: float = Field(gt=0)
    name: str | None = None

    def footprint(self, segments: int = 24) -> Polygon:
        return shapely.Point(self.base).buffer(self.radius, quad_segs=max(2, segments // 4))

    def edges(self, segments: int = 24) -> np.ndarray:
        """Top and bottom rings plus four vertical lines (a wireframe)."""
        a = np.linspace(0, 2 * np.pi, segments + 1)
        ring = np.c_[self.base[0] + self.radius * np.cos(a), self.base[1] + self.radius * np.sin(a)]
        edges = []
        for z in (0.0, self.height):
            pts = np.c_[ring, np.full(len(ring), z)]
            edges += [[pts[i], pts[i + 1]] for i in range(segments)]
        for i in range(0, segments, segments // 4):
            edges.append([[*ring[i], 0.0], [*ring[i], self.height]])
        return np.array(edges)


Obstacle = Annotated[Box | Cylinder, Field(discriminator="type")]


class Wall(_StandsOnGround):
    """A vertical wall from ``start`` to ``end`` on the ground: it occludes and cannot be walked through."""

    start: Vec2
    end: Vec2
    height: float = Field(gt=0)
    thickness: float = Field(0.2, gt=0)
    name: str | None = None

    @model_validator(mode="after")
    def _has_length(self) -> Wall:
        if not (np.isfinite(self.start).all() and np.isfinite(self.end).all()):
            raise ValueError("wall end points must be finite numbers")
        if np.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1]) < 1e-3:
            raise ValueError("wall start and end are the same point")
        return self

    def footprint(self) -> Polygon:
        return LineString([self.start, self.end]).buffer(self.thickness / 2, cap_style="flat")

    def edges(self) -> np.ndarray:
        (x0, y0), (x1, y1), h = self.start, self.end, self.height
        return np.array([
            [[x0, y0, 0], [x1, y1, 0]], [[x0, y0, h], [x1, y1, h]],
            [[x0, y0, 0], [x0, y0, h]], [[x1, y1, 0], [x1, y1, h]],
        ], dtype=np.float64)


class Layout(StrictModel):
    """Where people can stand (``walkable``) and what they can stand behind (``obstacles``, ``walls``), in metres on
    the ground (``frame: image`` layouts are drawn in pixels: :mod:`vc.scenes.pixel_layout`)."""

    frame: Literal["ground"] = "ground"
    walkable: Annotated[list[list[Vec2]], Field(min_length=1)]
    obstacles: list[Obstacle] = []
    walls: list[Wall] = []

    @field_validator("walkable")
    @classmethod
    def _simple_polygons(cls, polygons: list[list[list[float]]]) -> list[list[list[float]]]:
        for index, points in enumerate(polygons):
            try:
                validate_ground_polygon(points)
            except ValueError as error:
                raise ValueError(f"polygon {index}: {error}") from None
        return polygons

    def walkable_area(self) -> shapely.Geometry:
        """Union of the walkable polygons, in metres on the ground plane."""
        return shapely.union_all([Polygon(p) for p in self.walkable])

    def blockers(self) -> list[Box | Cylinder | Wall]:
        return [*self.obstacles, *self.walls]

    def standable_area(self) -> shapely.Geometry:
        """Walkable ground minus the footprints of obstacles and walls that stand on it."""
        area = self.walkable_area()
        footprints = [b.footprint() for b in self.blockers() if b.bottom <= GROUND_CONTACT_M]
        if footprints:
            area = area.difference(shapely.union_all(footprints))
        return area


def densify_segments(segments: np.ndarray, pieces: int = EDGE_PIECES) -> np.ndarray:
    """(N, 2, 3) segments -> (N, pieces + 1, 3) polylines, so projections through distortion curve."""
    s = np.linspace(0.0, 1.0, pieces + 1)[None, :, None]
    return segments[:, :1] * (1 - s) + segments[:, 1:2] * s
