"""Where people stand in a sample: feet on the walkable ground around a region, never inside each other.

Most people stand on the region's own ground polygon. Some are placed on purpose where detectors fail:

* across the region's border (a ring of ground outside its polygon): the crop shows them, another region owns
  them, and the network must still see them as people (docs/design.md, "Regions": labelled in every crop);
* where an obstacle hides part of the body from the camera (:func:`hidden_ground`): right behind a bollard, but
  metres behind a raised sign, whose shadow from the camera falls on the torsos of people far beyond its post.

People cut by the image border come from the same rules: a region's crop reaches the image border wherever its
ground does. Orientation is uniform or drawn from the scene's von Mises mixture (azimuth of the walking
direction, from +x towards +y).

Pedestrians walk in social groups as often as alone (Moussaïd, Perozo, Garnier, Helbing & Theraulaz, PLoS ONE
2010: most groups are pairs, few exceed four, and at low density they walk abreast, about 0.75 m apart). With the
scene's ``priors.group_rate``, a person placed starts a group (:data:`GROUP_SIZES`): the others walk beside
them, facing the same way, or in file behind them (:data:`IN_FILE_SHARE` of the groups). Side by side and one
behind another are where a detector's centre peaks merge: a network that never saw them cannot learn to keep
two people apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Point, Polygon

from vc.calibration.camera import Camera
from vc.scenes.layout import Box, Cylinder, Layout, Wall
from vc.scenes.schema import Priors

#: Width (m) of the ring around a region's polygon where border-straddling people stand.
BORDER_RING_M = 1.5
#: Heights on a standing person (m), shins to head: a person stands behind an obstacle when it hides one of them.
HIDDEN_BODY_HEIGHTS_M = (0.3, 0.55, 0.8, 1.05, 1.3, 1.55)
#: A person whose vertical axis passes this close (m) to a hidden point has that side of the body hidden.
BODY_HALF_WIDTH_M = 0.2
#: An obstacle that reaches the camera's height hides all the ground beyond it; that ground is cut this far (m)
#: beyond the obstacle (the region's surroundings cut it sooner).
HIDDEN_REACH_M = 60.0
#: Nobody stands closer than this to another person (m, between feet centres): shoulders do not interpenetrate.
MIN_SEPARATION_M = 0.6
#: Tries per person before a crowded sample settles for fewer people.
MAX_TRIES = 50
#: A sample holds up to one person per ``priors.m2_per_person`` of its region's ground, at least
#: :data:`MIN_MAX_PEOPLE`; at most :data:`CAP_AT_DEFAULT_DENSITY` at the default density (40 m2 a person), a cap that
#: bounds a large region's render time and grows with the density the scene states (24 at 10 m2 a person).
MIN_MAX_PEOPLE = 2
CAP_AT_DEFAULT_DENSITY = 6
#: Group sizes (people in all) and their chances: pairs most, few groups beyond four.
GROUP_SIZES = {2: 0.7, 3: 0.22, 4: 0.08}
#: Walking abreast: centre-to-centre spacing (m), stagger along the walking direction (m), heading spread (deg).
ABREAST_SPACING_M = (0.6, 0.9)
ABREAST_STAGGER_M = 0.3
GROUP_HEADING_SPREAD_DEG = 10.0
#: The share of groups that walk in file, and their spacing (m) and sideways sway (m).
IN_FILE_SHARE = 0.2
IN_FILE_SPACING_M = (1.0, 1.6)
IN_FILE_SWAY_M = 0.25


@dataclass(frozen=True)
class PlacementMix:
    """Shares of people placed on the region, across its border and behind obstacles (the rest)."""

    border: float = 0.2
    behind_obstacle: float = 0.15


@dataclass(frozen=True)
class Placement:
    position: tuple[float, float]  # feet, metres on the ground
    yaw_deg: float  # facing direction, from +x towards +y
    kind: str  # "region" | "border" | "behind_obstacle"


def default_max_people(region_ground: shapely.Geometry, m2_per_person: float) -> int:
    """The most people a sample of the region holds (see :data:`MIN_MAX_PEOPLE`); a sample draws 0 to this many."""
    cap = math.ceil(CAP_AT_DEFAULT_DENSITY * Priors.model_fields["m2_per_person"].default / m2_per_person)
    return int(np.clip(math.ceil(region_ground.area / m2_per_person), MIN_MAX_PEOPLE, max(cap, MIN_MAX_PEOPLE)))


def hidden_ground(camera_centre: np.ndarray, blocker: Box | Cylinder | Wall) -> shapely.Geometry:
    """Ground (m) where a person standing would have part of the body hidden by ``blocker`` from a camera at
    ``camera_centre`` (3,): for each of :data:`HIDDEN_BODY_HEIGHTS_M`, the obstacle's shadow on the plane at that
    height with the camera as the light, widened by :data:`BODY_HALF_WIDTH_M`.

    The ray from the camera to a body point at height z descends from the camera to z, so it can only meet the
    obstacle's part between z and the camera's height: that part, projected along the rays onto the plane z, is the
    set of hidden points at height z, and for a convex obstacle (box, cylinder, wall) it is the convex hull of its
    projected corners. A raised obstacle hides people far behind it (PETS09's sign, 2.4-3.1 m up on a post 18 m
    from a camera 7 m high, hides the torsos of people 3-10 m beyond the post); an obstacle above the camera hides
    no one. A camera standing on the obstacle's footprint (mounted on it) sees past it: no hidden ground.
    """
    footprint = blocker.footprint()
    camera_xy, camera_height = np.asarray(camera_centre[:2], np.float64), float(camera_centre[2])
    if footprint.contains(Point(camera_xy)):
        return Polygon()
    ring = np.asarray(footprint.exterior.coords)[:-1] - camera_xy  # corners relative to the camera's foot
    reach = np.maximum(np.hypot(ring[:, 0], ring[:, 1]), 1e-6)
    shadows = []
    for body in HIDDEN_BODY_HEIGHTS_M:
        low, high = max(blocker.bottom, body), min(blocker.top, camera_height)
        if low >= high:
            continue
        corners = []
        for z in (low, high):
            # a corner at height z lands on the plane `body` at (camera height - body) / (camera height - z) times its
            # horizontal distance; at the camera's own height never (cut at HIDDEN_REACH_M beyond the corner)
            scale = (camera_height - body) / (camera_height - z) if camera_height - z > 1e-6 else np.inf
            corners.append(ring * np.minimum(scale, 1.0 + HIDDEN_REACH_M / reach)[:, None])
        shadows.append(shapely.MultiPoint(np.concatenate(corners) + camera_xy).convex_hull)
    if not shadows:
        return Polygon()
    # widened after taking the obstacle out, so that standing in front of it, touching it, is not being behind it
    return shapely.union_all(shadows).difference(footprint).buffer(BODY_HALF_WIDTH_M).difference(footprint)


class _UniformPoints:
    """Points drawn uniformly over a ground area: a triangle of its constrained Delaunay triangulation by area,
    then a point in it. Nothing is rejected, so a thin wedge (a lamp post's shadow across a region) costs what a
    compact area does."""

    def __init__(self, area: shapely.Geometry) -> None:
        polygons = [part for part in shapely.get_parts(area) if part.geom_type == "Polygon" and part.area > 0]
        triangles = [np.asarray(triangle.exterior.coords)[:3] for polygon in polygons
                     for triangle in shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))]
        self.triangles = np.array(triangles, np.float64).reshape(-1, 3, 2)
        edges = self.triangles[:, 1:] - self.triangles[:, :1]
        areas = 0.5 * np.abs(edges[:, 0, 0] * edges[:, 1, 1] - edges[:, 0, 1] * edges[:, 1, 0])
        self.cumulative = np.cumsum(areas) / areas.sum() if len(areas) and areas.sum() > 0 else np.empty(0)

    def __bool__(self) -> bool:
        return bool(len(self.cumulative))

    def draw(self, rng: np.random.Generator) -> np.ndarray:
        triangle = self.triangles[min(int(np.searchsorted(self.cumulative, rng.random(), side="right")),
                                      len(self.triangles) - 1)]
        u, v = rng.random(2)
        if u + v > 1.0:  # fold the far half of the parallelogram back onto the triangle
            u, v = 1.0 - u, 1.0 - v
        return triangle[0] + u * (triangle[1] - triangle[0]) + v * (triangle[2] - triangle[0])


class PlacementSampler:
    """Samples :class:`Placement` s for one region of a scene."""

    def __init__(self, camera: Camera, layout: Layout, region_ground: shapely.Geometry, priors: Priors,
                 mix: PlacementMix = PlacementMix()) -> None:
        self.priors, self.mix = priors, mix
        standable = layout.standable_area()
        near = region_ground.buffer(BORDER_RING_M)
        # ground hidden by each obstacle near the region; an obstacle is drawn first, then a point behind it, so that
        # a sign's few square metres are drawn as often as a lamp post's long thin shadow
        hidden = [hidden_ground(camera.center, blocker).intersection(near).intersection(standable)
                  for blocker in layout.blockers()]
        self.areas = {
            "region": region_ground.intersection(standable),
            "border": near.difference(region_ground).intersection(standable),
            "behind_obstacle": shapely.union_all(hidden) if hidden else Polygon(),
        }
        # per kind, a sampler for each of its non-empty areas (behind obstacles: one per obstacle)
        areas = {"region": [self.areas["region"]], "border": [self.areas["border"]], "behind_obstacle": hidden}
        self._points = {kind: [points for points in map(_UniformPoints, pieces) if points]
                        for kind, pieces in areas.items()}
        if not self._points["region"]:
            raise ValueError("the region has no standable ground")
        self.standable = standable
        shapely.prepare(self.standable)

    def _kind(self, rng: np.random.Generator) -> str:
        draw = rng.random()
        if draw < self.mix.border and self._points["border"]:
            return "border"
        if draw < self.mix.border + self.mix.behind_obstacle and self._points["behind_obstacle"]:
            return "behind_obstacle"
        return "region"

    def _point(self, kind: str, rng: np.random.Generator) -> np.ndarray:
        """A point of ``kind``'s ground, uniform over it (behind obstacles: over one obstacle's, drawn first)."""
        samplers = self._points[kind]
        return samplers[int(rng.integers(len(samplers))) if len(samplers) > 1 else 0].draw(rng)

    def _yaw(self, rng: np.random.Generator) -> float:
        if self.priors.orientation == "uniform":
            return float(rng.uniform(-180.0, 180.0))
        weights = np.array([component.weight for component in self.priors.orientation])
        component = self.priors.orientation[rng.choice(len(weights), p=weights / weights.sum())]
        angle = math.radians(component.mean_deg) + (rng.vonmises(0.0, component.kappa) if component.kappa > 0
                                                     else rng.uniform(-math.pi, math.pi))
        return float((math.degrees(angle) + 180.0) % 360.0 - 180.0)

    def _free(self, point: np.ndarray, placed: list[Placement]) -> bool:
        return all(math.dist(point, other.position) >= MIN_SEPARATION_M for other in placed)

    def _companions(self, leader: Placement, size: int, rng: np.random.Generator) -> list[Placement]:
        """Where the other ``size - 1`` members of ``leader``'s group walk (before checking the ground): abreast,
        alternately to the leader's left and right, or in file behind."""
        heading = math.radians(leader.yaw_deg)
        forward, left = np.array([math.cos(heading), math.sin(heading)]), np.array([-math.sin(heading),
                                                                                   math.cos(heading)])
        in_file = rng.random() < IN_FILE_SHARE
        members, lateral, behind = [], 0.0, 0.0
        for index in range(1, size):
            if in_file:
                behind += rng.uniform(*IN_FILE_SPACING_M)
                offset = -behind * forward + rng.uniform(-IN_FILE_SWAY_M, IN_FILE_SWAY_M) * left
            else:
                side = 1.0 if index % 2 else -1.0
                lateral = abs(lateral) + rng.uniform(*ABREAST_SPACING_M) if side > 0 else -lateral
                offset = lateral * left + rng.uniform(-ABREAST_STAGGER_M, ABREAST_STAGGER_M) * forward
            yaw = leader.yaw_deg + rng.uniform(-GROUP_HEADING_SPREAD_DEG, GROUP_HEADING_SPREAD_DEG)
            position = np.asarray(leader.position) + offset
            members.append(Placement((float(position[0]), float(position[1])), float(yaw), leader.kind))
        return members

    def _one(self, placed: list[Placement], rng: np.random.Generator) -> Placement | None:
        """A person on free ground, or None after :data:`MAX_TRIES`."""
        for _ in range(MAX_TRIES):
            kind = self._kind(rng)
            point = self._point(kind, rng)
            if self._free(point, placed):
                return Placement((float(point[0]), float(point[1])), self._yaw(rng), kind)
        return None

    def sample(self, count: int, rng: np.random.Generator) -> list[Placement]:
        """Up to ``count`` people, at least :data:`MIN_SEPARATION_M` apart (fewer if the ground is crowded); with
        ``priors.group_rate``, some of them in groups (a member who would stand off the ground or too close to
        someone is left out)."""
        placed: list[Placement] = []
        left = count
        while left > 0:
            left -= 1
            person = self._one(placed, rng)
            if person is None:
                continue
            placed.append(person)
            if self.priors.group_rate > 0 and left > 0 and rng.random() < self.priors.group_rate:
                size = int(rng.choice(list(GROUP_SIZES), p=list(GROUP_SIZES.values())))
                for member in self._companions(person, min(size, left + 1), rng):
                    if self.standable.contains(Point(member.position)) and self._free(member.position, placed):
                        placed.append(member)
                        left -= 1
        return placed
