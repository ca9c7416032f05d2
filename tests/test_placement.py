"""Placement: feet on standable ground around the region, apart from each other, orientation from the prior."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon

from vc.calibration.camera import Camera, look_at
from vc.render.placement import (
    BODY_HALF_WIDTH_M,
    BORDER_RING_M,
    HIDDEN_BODY_HEIGHTS_M,
    MIN_SEPARATION_M,
    PlacementSampler,
    default_max_people,
    hidden_ground,
)
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


def _hidden_body_height(camera_centre: np.ndarray, box: Box, feet: np.ndarray) -> bool:
    """Whether the segment from the camera to one of the body heights above ``feet`` passes through the
    axis-aligned ``box`` (slab test): the ground truth that :func:`hidden_ground` approximates."""
    low, high = np.asarray(box.center) - np.asarray(box.size) / 2, np.asarray(box.center) + np.asarray(box.size) / 2
    for body in HIDDEN_BODY_HEIGHTS_M:
        direction = np.array([*feet, body]) - camera_centre
        with np.errstate(divide="ignore", invalid="ignore"):
            t0, t1 = (low - camera_centre) / direction, (high - camera_centre) / direction
        enter, leave = np.nanmax(np.minimum(t0, t1)), np.nanmin(np.maximum(t0, t1))
        if enter <= leave and leave > 0 and enter < 1:
            return True
    return False


@pytest.mark.parametrize("box", [Box(type="box", center=[0.0, 0.0, 0.5], size=[1.0, 1.0, 1.0]),
                                 Box(type="box", center=[0.0, 0.0, 2.75], size=[0.6, 0.1, 0.7])],
                         ids=["on the ground", "raised sign"])
def test_hidden_ground_is_where_the_obstacle_hides_part_of_a_standing_person(box: Box) -> None:
    centre = CAMERA.center
    area = hidden_ground(centre, box)
    xs, ys = np.meshgrid(np.arange(-3.0, 3.0, 0.1), np.arange(-3.0, 12.0, 0.1))
    grid = np.c_[xs.ravel(), ys.ravel()]
    hidden = np.array([_hidden_body_height(centre, box, point) for point in grid])
    outside = ~shapely.contains_xy(box.footprint(), grid[:, 0], grid[:, 1])
    inside = shapely.contains_xy(area, grid[:, 0], grid[:, 1])
    # every feet position with a body height hidden is in the area...
    assert hidden[outside].sum() > 20 and inside[hidden & outside].all()
    # ...and the area reaches no further than half a body's width from one (or from the obstacle itself)
    hidden_points = shapely.MultiPoint(grid[hidden])
    assert all(shapely.distance(hidden_points, Point(point)) <= BODY_HALF_WIDTH_M + 0.15 for point in grid[inside])


def test_a_raised_sign_hides_people_metres_behind_it_and_not_right_behind() -> None:
    sign = Box(type="box", center=[0.0, 0.0, 2.75], size=[0.6, 0.1, 0.7])  # camera 6 m up, 12 m away
    area = hidden_ground(CAMERA.center, sign)
    # the sign's bottom edge (2.4 m) falls on a head (1.55 m) 2.8 m beyond it, its top on the shins 11.7 m beyond
    assert 2.3 < area.bounds[1] < 3.0 and 11.4 < area.bounds[3] < 12.2


def test_nothing_is_hidden_by_an_obstacle_above_the_camera_or_holding_it() -> None:
    canopy = Box(type="box", center=[0.0, 0.0, 7.0], size=[2.0, 2.0, 1.0])  # above the camera's 6 m
    assert hidden_ground(CAMERA.center, canopy).is_empty
    mast = Box(type="box", center=[0.0, -12.0, 3.0], size=[0.5, 0.5, 6.0])  # the camera is mounted on it
    assert hidden_ground(CAMERA.center, mast).is_empty


def test_people_are_drawn_behind_each_obstacle_in_turn() -> None:
    sign = Box(type="box", center=[2.0, 0.0, 2.75], size=[0.6, 0.1, 0.7])
    layout = Layout(walkable=LAYOUT.walkable, obstacles=[*LAYOUT.obstacles, sign])
    sampler = PlacementSampler(CAMERA, layout, REGION, Priors())
    rng = np.random.default_rng(3)
    points = np.array([sampler._point("behind_obstacle", rng) for _ in range(400)])
    behind = [shapely.contains_xy(hidden_ground(CAMERA.center, obstacle), points[:, 0], points[:, 1]).mean()
              for obstacle in layout.obstacles]
    assert all(0.35 < share < 0.65 for share in behind), behind


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
