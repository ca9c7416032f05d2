"""Placement: feet on standable ground around the region, apart from each other, orientation from the prior."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Point, Polygon

from vc.calibration.camera import Camera, look_at
from vc.render.placement import BORDER_RING_M, MIN_SEPARATION_M, PlacementSampler, default_max_people
from vc.scenes.layout import Box, Layout
from vc.scenes.schema import Priors, VonMises

CAMERA = Camera(320, 240, np.array([[300.0, 0.0, 160.0], [0.0, 300.0, 120.0], [0.0, 0.0, 1.0]]),
                *look_at([0.0, -12.0, 6.0], [0.0, 0.0, 0.0]))
LAYOUT = Layout(walkable=[[[-8.0, -6.0], [8.0, -6.0], [8.0, 8.0], [-8.0, 8.0]]],
                obstacles=[Box(type="box", center=[0.0, 0.0, 0.5], size=[1.0, 1.0, 1.0])])
REGION = Polygon([(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)])


def test_people_stand_on_standable_ground_near_the_region_and_apart() -> None:
    sampler = PlacementSampler(CAMERA, LAYOUT, REGION, Priors())
    rng = np.random.default_rng(0)
    standable = LAYOUT.standable_area()
    near = REGION.buffer(BORDER_RING_M + 1e-6)
    kinds = set()
    for _ in range(200):
        people = sampler.sample(5, rng)
        for person in people:
            point = Point(person.position)
            assert standable.contains(point) and near.contains(point)
            kinds.add(person.kind)
        for a in range(len(people)):
            for b in range(a + 1, len(people)):
                assert math.dist(people[a].position, people[b].position) >= MIN_SEPARATION_M
    assert kinds == {"region", "border", "behind_obstacle"}


def test_behind_obstacle_means_beyond_it_as_seen_from_the_camera() -> None:
    sampler = PlacementSampler(CAMERA, LAYOUT, REGION, Priors())
    area = sampler.areas["behind_obstacle"]
    assert not area.is_empty
    # The camera is at y = -12 looking at +y: the hidden ground lies beyond the box (y > 0.5).
    assert area.bounds[1] >= 0.5 - 1e-6
    assert shapely.distance(area, LAYOUT.obstacles[0].footprint()) < 1e-6


def test_orientation_follows_a_von_mises_prior() -> None:
    priors = Priors(orientation=[VonMises(mean_deg=90.0, kappa=8.0)])
    sampler = PlacementSampler(CAMERA, LAYOUT, REGION, priors)
    rng = np.random.default_rng(1)
    yaws = np.array([p.yaw_deg for _ in range(100) for p in sampler.sample(3, rng)])
    mean = math.degrees(math.atan2(np.sin(np.radians(yaws)).mean(), np.cos(np.radians(yaws)).mean()))
    assert abs(mean - 90.0) < 5.0 and np.abs(yaws - 90.0).max() < 120.0


def test_same_generator_state_gives_the_same_people() -> None:
    sampler = PlacementSampler(CAMERA, LAYOUT, REGION, Priors())
    first = sampler.sample(4, np.random.default_rng(7))
    assert first == sampler.sample(4, np.random.default_rng(7))


def _nearest_pairs(people) -> list[tuple[float, float]]:
    """(distance m, heading difference deg) from each person to their nearest neighbour."""
    pairs = []
    for a, person in enumerate(people):
        others = [other for b, other in enumerate(people) if b != a]
        if others:
            nearest = min(others, key=lambda other: math.dist(person.position, other.position))
            turn = abs((person.yaw_deg - nearest.yaw_deg + 180.0) % 360.0 - 180.0)
            pairs.append((math.dist(person.position, nearest.position), turn))
    return pairs


def test_groups_walk_together_and_no_groups_leaves_the_draws_unchanged() -> None:
    alone = PlacementSampler(CAMERA, LAYOUT, REGION, Priors())
    grouped = PlacementSampler(CAMERA, LAYOUT, REGION, Priors(group_rate=1.0))
    close_alone, close_grouped, turns = [], [], []
    for seed in range(100):
        close_alone += [d for d, _ in _nearest_pairs(alone.sample(4, np.random.default_rng(seed)))]
        people = grouped.sample(4, np.random.default_rng(seed))
        assert len(people) <= 4
        for a in range(len(people)):
            for b in range(a + 1, len(people)):
                assert math.dist(people[a].position, people[b].position) >= MIN_SEPARATION_M
        pairs = _nearest_pairs(people)
        close_grouped += [d for d, _ in pairs]
        turns += [turn for d, turn in pairs if d <= 0.95]
    # Group members face the same way, within twice the heading spread of each other (a stranger passing by
    # closer than a metre need not).
    assert np.mean(np.array(turns) <= 20.0 + 1e-9) > 0.9
    # Alone, a neighbour within a metre is rare; in groups, the usual case.
    assert np.mean(np.array(close_alone) <= 1.0) < 0.15 < 0.6 < np.mean(np.array(close_grouped) <= 1.0)
    # group_rate 0 draws exactly what the sampler drew before groups existed (renders stay byte-identical).
    first = [(p.position, p.yaw_deg) for p in alone.sample(5, np.random.default_rng(7))]
    again = PlacementSampler(CAMERA, LAYOUT, REGION, Priors(group_rate=0.0))
    assert first == [(p.position, p.yaw_deg) for p in again.sample(5, np.random.default_rng(7))]


def test_a_busier_scene_puts_more_people_in_a_sample() -> None:
    """One person per ``m2_per_person`` of region ground: the default density keeps its 2-6, a crowd's cap grows."""
    def most(area_m2: float, m2_per_person: float) -> int:
        side = math.sqrt(area_m2)
        return default_max_people(shapely.box(0.0, 0.0, side, side), m2_per_person)

    default = Priors().m2_per_person
    assert [most(area, default) for area in (10.0, 89.7, 180.0, 1000.0)] == [2, 3, 5, 6]
    assert [most(area, 10.0) for area in (10.0, 89.7, 1000.0)] == [2, 9, 24]
