"""The miss analysis (vc.evaluation.misses): every person and false positive at the operating point, sorted by kind."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vc.deploy.runtime import Person
from vc.evaluation.draw import ANNOTATED_AREA_COLOUR, OUTCOME_COLOURS, draw_errors
from vc.evaluation.metrics import ImageResult
from vc.evaluation.misses import analyse_misses, region_lookup
from vc.evaluation.plots import plot_miss_analysis

A = [10, 100, 30, 160]  # found, and detected twice
B = [200, 100, 220, 160]  # seen by a box 1.5x too wide, half its width to the right
C = [400, 100, 420, 160]  # nobody near
D, E = [300, 100, 320, 160], [314, 100, 334, 160]  # side by side, one box over both
FOUND_ELSEWHERE = [[40 * k, 300, 40 * k + 20, 360] for k in range(6)]


def _errors_frame() -> ImageResult:
    detections = np.array([A, [600, 10, 620, 70], [205, 100, 235, 160], [12, 102, 32, 162], [298, 98, 336, 162]],
                          float)
    return ImageResult(truth_boxes=np.array([A, B, C, D, E], float), boxes=detections,
                       scores=np.array([0.95, 0.9, 0.85, 0.8, 0.75]))


def _clean_frame() -> ImageResult:
    boxes = np.array(FOUND_ELSEWHERE, float)
    return ImageResult(truth_boxes=boxes, boxes=boxes + 1.0, scores=np.linspace(0.6, 0.5, len(boxes)))


@pytest.fixture(scope="module")
def analysis():
    def region_of(points):
        return ["left" if x < 100 else "right" for x, _ in points]

    return analyse_misses([_errors_frame(), _clean_frame()], [7, 8], region_of)


def test_every_person_and_false_positive_gets_its_kind(analysis):
    assert analysis.score_threshold == pytest.approx(0.5)  # best F1 keeps every detection here
    assert analysis.outcomes() == {"found": 7, "near miss": 3, "missed": 1}
    assert analysis.outcomes(grouped=True) == {"found": 0, "near miss": 2, "missed": 0}  # D and E
    assert analysis.false_positive_kinds() == {"duplicate": 1, "merged": 1, "misplaced": 1,
                                               "outside the annotated area": 0, "background": 1}
    assert analysis.precision == pytest.approx(7 / 11) and analysis.recall == pytest.approx(7 / 11)


def test_a_near_miss_measures_the_box_that_nearly_matched(analysis):
    near_b = next(person for person in analysis.people if list(person.box) == B)
    assert near_b.outcome == "near miss" and not near_b.nearest_found_another
    error = near_b.box_error()
    assert error["width_ratio"] == pytest.approx(1.5) and error["height_ratio"] == pytest.approx(1.0)
    assert error["x_offset"] == pytest.approx(0.5) and error["y_offset"] == pytest.approx(0.0)
    assert next(person for person in analysis.people if list(person.box) == C).box_error() is None


def test_recall_is_broken_down_by_group_height_and_region(analysis):
    assert analysis.recall_by_group() == {"apart": {"people": 9, "recall": round(7 / 9, 4)},
                                          "overlapping another": {"people": 2, "recall": 0.0}}
    assert analysis.recall_by_height() == {"60-80 px": {"people": 11, "recall": round(7 / 11, 4)}}
    # Feet of A and of the first three clean people (x < 100) are "left": all found.
    assert analysis.recall_by_region()["left"] == {"people": 4, "recall": 1.0}
    assert analysis.recall_by_region()["right"] == {"people": 7, "recall": round(3 / 7, 4)}


def test_recall_is_broken_down_by_the_frames_edge_when_its_size_is_given():
    cut = [700, 100, 720, 160]  # walking in at the right edge of a 720 px wide frame, the box clipped there
    near = [670, 300, 690, 360]  # 30 px from the edge: half of its 60 px height
    inside = [300, 150, 320, 210]  # 150 px from the nearest edge (the top): 2.5 heights
    truth = np.array([cut, near, inside], float)
    image = ImageResult(truth, np.array([near, inside], float), np.array([0.9, 0.8]))
    analysis = analyse_misses([image], [1], frame_size=(720, 400))
    assert analysis.recall_by_edge() == {"cut by the frame": {"people": 1, "recall": 0.0},
                                         "0.5-2 heights from an edge": {"people": 1, "recall": 1.0},
                                         ">= 2 heights": {"people": 1, "recall": 1.0}}
    assert analysis.summary()["recall_by_edge"] == analysis.recall_by_edge()
    missed = analysis.to_dict()["people"]
    assert [person["edge_px"] for person in missed] == [0.0]
    # without the frame's size nothing is broken down by it
    unsized = analyse_misses([image], [1])
    assert unsized.recall_by_edge() == {} and "recall_by_edge" not in unsized.summary()
    assert "edge_px" not in unsized.to_dict()["people"][0]


def test_the_worst_frames_are_those_with_most_errors(analysis):
    assert analysis.frame_errors() == {7: 8, 8: 0}  # 4 people not found, 4 false positives
    assert analysis.worst_frames(5) == [7]  # a frame without errors is not shown
    report = json.loads(json.dumps(analysis.to_dict()))
    assert len(report["people"]) == 4 and len(report["false_positive_list"]) == 4
    assert report["near_miss_box_errors"]["width_ratio"]["median"] > 1.0


def test_a_neighbours_box_is_told_from_a_misplaced_one():
    left, right = [100, 100, 120, 160], [108, 100, 128, 160]
    image = ImageResult(np.array([left, right], float), np.array([left], float), np.array([0.9]))
    (found, near), = [analyse_misses([image], [1]).people]
    assert found.outcome == "found" and near.outcome == "near miss" and near.nearest_found_another


def test_no_detections_have_no_operating_point():
    image = ImageResult(np.array([A], float), np.zeros((0, 4)), np.zeros(0))
    assert analyse_misses([image], [1]) is None


def test_regions_are_looked_up_in_the_bundles_geojson_areas():
    square = {"type": "Polygon", "coordinates": [[[0, 0], [100, 0], [100, 100], [0, 100], [0, 0]]]}
    region_of = region_lookup({"near": square, "also": square})
    assert region_of(np.array([[50.0, 50.0], [150.0, 50.0]])) == ["near", None]  # the first region wins


def test_the_figure_and_the_error_sheet_are_drawn(analysis, tmp_path):
    plot_miss_analysis(analysis, tmp_path / "misses.png", "test")
    assert (tmp_path / "misses.png").stat().st_size > 10_000
    frame = np.zeros((400, 700, 3), np.uint8)
    person = Person("left", 0.95, np.array(A, float), np.zeros((17, 3)), np.zeros((0, 0), bool), (0, 0))
    drawn = draw_errors(frame, 7, [person], [p for p in analysis.people if p.frame == 7],
                        [f for f in analysis.false_positives if f.frame == 7])
    assert tuple(drawn[130, C[0]]) == OUTCOME_COLOURS["missed"]  # the missed person's box edge is red
    assert tuple(drawn[130, B[0]]) == OUTCOME_COLOURS["near miss"]
    # The annotated area is outlined when given, and only then.
    area = np.array([[500, 250], [690, 250], [690, 390], [500, 390]], float)
    outlined = draw_errors(frame, 7, [person], [], [], area)
    assert tuple(outlined[320, 499:502].max(axis=0)) == ANNOTATED_AREA_COLOUR and not drawn[320, 499:502].any()
