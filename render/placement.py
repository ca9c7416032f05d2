"""Where people stand in a sample: feet on the walkable ground around a region, never inside each other.

Most people stand on the region's own ground polygon. Some are placed on purpose where detectors fail:

* across the region's border (a ring of ground outside its polygon): the crop shows them, another region owns
  them, and the network must still see them as people (DESIGN.md, "Regions": labelled in every crop);
* just behind an obstacle as seen from the camera, so that part of the body is hidden.

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
import shapely.affinity
from shapely.geometry import Point

from vc.calibration.camera import Camera
from vc.scenes.layout import Layout
from vc.scenes.schema import Priors

#: Width (m) of the ring around a region's polygon where border-straddling people stand.
BORDER_RING_M = 1.5
#: People "behind an obstacle" stand within this distance (m) of its far side, seen from the camera.
BEHIND_OBSTACLE_M = 1.2
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


class PlacementSampler:
    """Samples :class:`Placement` s for one region of a scene."""

    def __init__(self, camera: Camera, layout: Layout, region_ground: shapely.Geometry, priors: Priors,
                 mix: PlacementMix = PlacementMix()) -> None:
        self.priors, self.mix = priors, mix
        standable = layout.standable_area()
        self.areas = {
            "region": region_ground.intersection(standable),
            "border": region_ground.buffer(BORDER_RING_M).difference(region_ground).intersection(standable),
            "behind_obstacle": self._behind_obstacles(camera, layout, region_ground.buffer(BORDER_RING_M))
            .intersection(standable),
        }
        if self.areas["region"].is_empty:
            raise ValueError("the region has no standable ground")
        self._prepared = {kind: area for kind, area in self.areas.items() if not area.is_empty}
        for area in self._prepared.values():
            shapely.prepare(area)
        self.standable = standable
        shapely.prepare(self.standable)

    @staticmethod
    def _behind_obstacles(camera: Camera, layout: Layout, near: shapely.Geometry) -> shapely.Geometry:
        """Ground just beyond each obstacle's footprint, away from the camera: where it hides people."""
        centre = camera.center[:2]
        pieces = []
        for blocker in layout.blockers():
            footprint = blocker.footprint()
            if not footprint.intersects(near):
                continue
            away = np.asarray(footprint.centroid.coords[0]) - centre
            distance = float(np.linalg.norm(away))
            if distance < 1e-6:
                continue
            shift = away / distance * BEHIND_OBSTACLE_M
            swept = shapely.union_all([shapely.affinity.translate(footprint, *(shift * s)) for s in (0.5, 1.0)])
            pieces.append(shapely.convex_hull(shapely.union(footprint, swept)).difference(footprint))
        return shapely.union_all(pieces).intersection(near) if pieces else shapely.Polygon()

    def _kind(self, rng: np.random.Generator) -> str:
        draw = rng.random()
        if draw < self.mix.border and "border" in self._prepared:
            return "border"
        if draw < self.mix.border + self.mix.behind_obstacle and "behind_obstacle" in self._prepared:
            return "behind_obstacle"
        return "region"

    def _point_in(self, area: shapely.Geometry, rng: np.random.Generator) -> np.ndarray | None:
        x0, y0, x1, y1 = area.bounds
        for _ in range(MAX_TRIES):
            point = rng.uniform([x0, y0], [x1, y1])
            if area.contains(Point(point)):
                return point
        return None

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
            point = self._point_in(self._prepared[kind], rng)
            if point is not None and self._free(point, placed):
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
