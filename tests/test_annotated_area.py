"""Where a ground truth annotates people (vc.evaluation.annotated_area), and scoring inside it."""

from __future__ import annotations

import numpy as np
import pytest

from vc.deploy.boxes import foot_points
from vc.evaluation.annotated_area import MIN_FEET, AnnotatedArea
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.misses import OUTSIDE_ANNOTATED_AREA, analyse_misses


def _person(feet_x: float, feet_y: float, height: float = 60.0) -> list[float]:
    return [feet_x - height / 6, feet_y - height, feet_x + height / 6, feet_y]


def _truth_on_a_trapezoid() -> dict[int, np.ndarray]:
    """People whose feet fill the trapezoid (100, 200) (500, 200) (600, 400) (0, 400), frame by frame."""
    rng = np.random.default_rng(3)
    corners = [(100, 200), (500, 200), (600, 400), (0, 400)]
    truth = {frame: np.array([_person(x, y) for x, y in corners]) for frame in (1, 2)}
    for frame in range(3, 30):
        y = rng.uniform(200, 400, 3)
        x = rng.uniform(100 - (y - 200) / 2, 500 + (y - 200) / 2)
        truth[frame] = np.array([_person(a, b) for a, b in zip(x, y, strict=True)])
    return truth


def test_the_area_is_the_hull_of_the_ground_truths_feet():
    area = AnnotatedArea.of(_truth_on_a_trapezoid())
    assert sorted(map(tuple, area.polygon.round())) == [(0, 400), (100, 200), (500, 200), (600, 400)]
    assert area.feet == 8 + 27 * 3
    inside = [_person(300, 300), _person(100, 200), _person(50, 399)]  # middle, a corner, near the slanted edge
    outside = [_person(300, 150), _person(20, 250), _person(650, 400), _person(300, 401)]
    assert area.contains(np.array(inside)).all()
    assert not area.contains(np.array(outside)).any()
    # Whichever way the hull's vertices run.
    reversed_area = AnnotatedArea(area.polygon[::-1], area.feet)
    np.testing.assert_array_equal(reversed_area.contains(np.array(inside + outside)), [True] * 3 + [False] * 4)


@pytest.mark.parametrize("truth", [{1: np.zeros((0, 4))}, {1: np.array([_person(10 * k, 300) for k in range(20)])},
                                   {1: np.array([_person(100, 100)] * MIN_FEET)},
                                   {1: np.array([_person(k, k) for k in range(MIN_FEET - 1)])}],
                         ids=["nobody", "feet on one line", "one foot point", "too few feet"])
def test_a_ground_truth_spanning_no_area_leaves_every_detection_in(truth):
    area = AnnotatedArea.of(truth)
    assert area.polygon is None and area.to_dict()["polygon"] is None
    assert area.contains(np.array([_person(-1e6, 1e6), _person(5, 5)])).all()


def test_a_detection_outside_the_area_counts_only_when_it_finds_someone():
    truth = np.array([_person(300, 300)])
    unannotated, person = _person(300, 100), _person(300, 300)
    area = AnnotatedArea(np.array([[0, 200], [600, 200], [600, 400], [0, 400]], float), 0)
    # The unannotated person ranks first: a false positive in the plain AP, not held against it in the area.
    image = ImageResult(truth, np.array([unannotated, person]), np.array([0.9, 0.8]))
    assert evaluate([image]).ap50 == pytest.approx(0.5)
    assert area.evaluate_inside([image]).ap50 == pytest.approx(1.0)
    # A detection marked ignore that does find someone is a match as usual.
    found = evaluate([ImageResult(truth, np.array([person]), np.array([0.9]), detection_ignore=np.array([True]))])
    assert found.ap50 == pytest.approx(1.0) and found.matches == [[(0, 0)]]


def test_the_miss_analysis_tells_people_outside_the_annotated_area_from_background():
    truth = np.array([_person(300, 300)])
    detections = np.array([_person(300, 300), _person(300, 100), _person(100, 300)])
    area = AnnotatedArea(np.array([[0, 200], [600, 200], [600, 400], [0, 400]], float), 0)
    image = ImageResult(truth, detections, np.array([0.7, 0.9, 0.8]))  # the operating point keeps all three
    kinds = analyse_misses([image], [1], annotated_area=area).false_positive_kinds()
    assert kinds[OUTSIDE_ANNOTATED_AREA] == 1 and kinds["background"] == 1
    assert analyse_misses([image], [1]).false_positive_kinds()["background"] == 2


def test_foot_points_are_bottom_centres():
    np.testing.assert_allclose(foot_points(np.array([[10, 20, 30, 80]])), [[20, 80]])
