"""The one metrics implementation: AP50 (VOC all-point), PCKh@0.5 with head = height / 8, mask IoU."""

from __future__ import annotations

import numpy as np
import pytest

from vc.deploy.boxes import box_iou
from vc.evaluation.metrics import ImageResult, average_precision, evaluate

TRUTH = np.array([[10.0, 10.0, 30.0, 70.0], [50.0, 20.0, 70.0, 80.0]])


def test_box_iou() -> None:
    iou = box_iou(np.array([[0.0, 0.0, 10.0, 10.0]]), np.array([[5.0, 0.0, 15.0, 10.0], [20.0, 20.0, 30.0, 30.0]]))
    np.testing.assert_allclose(iou, [[50 / 150, 0.0]])


def test_perfect_detections_give_ap_one() -> None:
    result = evaluate([ImageResult(TRUTH, TRUTH.copy(), np.array([0.9, 0.8]))])
    assert result.ap50 == pytest.approx(1.0)
    assert result.to_dict()["matched"] == result.to_dict()["ground_truth"] == 2


def test_false_positive_ranked_first_and_a_miss() -> None:
    """Ranks: FP (0.95), TP (0.9); one of two people missed -> precision envelope 0.5 over recall 0..0.5."""
    boxes = np.array([[200.0, 200.0, 220.0, 260.0], TRUTH[0]])
    result = evaluate([ImageResult(TRUTH, boxes, np.array([0.95, 0.9]))])
    assert result.ap50 == pytest.approx(0.25)
    np.testing.assert_allclose(result.precision, [0.0, 0.5])
    np.testing.assert_allclose(result.recall, [0.0, 0.5])


def test_a_duplicate_detection_is_a_false_positive() -> None:
    result = evaluate([ImageResult(TRUTH[:1], np.array([TRUTH[0], TRUTH[0] + 1]), np.array([0.9, 0.8]))])
    assert result.ap50 == pytest.approx(1.0)  # the duplicate ranks after full recall
    np.testing.assert_allclose(result.precision, [1.0, 0.5])


def test_all_point_interpolation_matches_a_hand_computed_curve() -> None:
    # Ranked hits: TP, FP, TP, FP, TP with 4 ground truths -> envelope 1 (r .25), 2/3 (r .5), 3/5 (r .75).
    precision = np.array([1, 1 / 2, 2 / 3, 2 / 4, 3 / 5])
    recall = np.array([0.25, 0.25, 0.5, 0.5, 0.75])
    assert average_precision(precision, recall) == pytest.approx(0.25 * 1 + 0.25 * 2 / 3 + 0.25 * 3 / 5)


def test_pckh_uses_an_eighth_of_the_height_as_head_size() -> None:
    truth_keypoints = np.zeros((1, 17, 3))
    truth_keypoints[0, :, :2] = [20.0, 40.0]
    truth_keypoints[0, :, 2] = 2
    truth_keypoints[0, 16, 2] = 0  # unlabelled: not counted
    predicted = truth_keypoints[:, :, :2].copy()
    predicted[0, :8, 0] += 3.7  # height 60 -> head 7.5 -> threshold 3.75: correct
    predicted[0, 8:12, 0] += 3.8  # just beyond: wrong
    result = evaluate([ImageResult(TRUTH[:1], TRUTH[:1], np.array([0.9]), truth_keypoints, predicted)])
    assert result.pckh == pytest.approx(12 / 16)
    assert np.isnan(result.pckh_per_keypoint[16])
    np.testing.assert_array_equal(result.pckh_per_keypoint[8:12], 0.0)


def test_mask_iou_of_matched_people() -> None:
    truth = np.zeros((8, 8), bool)
    truth[2:6, 2:6] = True
    predicted = np.zeros_like(truth)
    predicted[2:6, 4:8] = True
    result = evaluate([ImageResult(TRUTH[:1], TRUTH[:1], np.array([0.9]), truth_masks=[truth], masks=[predicted])])
    assert result.mask_iou == pytest.approx(8 / 24)


def test_no_detections_and_no_truth() -> None:
    empty = np.zeros((0, 4))
    assert evaluate([ImageResult(TRUTH, empty, np.zeros(0))]).ap50 == 0.0
    assert evaluate([ImageResult(empty, empty, np.zeros(0))]).ap50 == 0.0


def test_ignored_truth_is_neither_a_miss_nor_a_match() -> None:
    truth = np.array([[0, 0, 10, 20], [50, 0, 60, 20]], float)
    found_both = ImageResult(truth_boxes=truth, boxes=truth + 0.5, scores=np.array([0.9, 0.8]),
                             truth_ignore=np.array([False, True]))
    evaluation = evaluate([found_both])
    assert evaluation.ap50 == 1.0 and evaluation.ground_truth == 1
    assert len(evaluation.scores) == 1 and evaluation.matches == [[(0, 0)]]
    # Missing the ignored person costs nothing; a detection far from everyone is still a false positive.
    stray = ImageResult(truth_boxes=truth, boxes=np.array([[0, 0, 10, 20], [100, 0, 110, 20]], float),
                        scores=np.array([0.5, 0.9]), truth_ignore=np.array([False, True]))
    assert evaluate([stray]).ap50 == pytest.approx(0.5)


def test_recall_of_people_in_groups_counts_the_ones_a_merged_detection_loses() -> None:
    # Two people one behind the other (IoU 0.6) found by one box, a third apart and found: overall recall 2/3,
    # the pair's 1/2. A pair whose partner is too hidden to ask for (ignored) is still a group of one.
    pair = np.array([[10.0, 10.0, 30.0, 70.0], [12.0, 14.0, 32.0, 76.0]])
    apart = np.array([[100.0, 10.0, 120.0, 70.0]])
    one_for_two = ImageResult(np.vstack([pair, apart]), np.vstack([pair[:1], apart]), np.array([0.9, 0.8]))
    evaluation = evaluate([one_for_two])
    assert evaluation.recall[-1] == pytest.approx(2 / 3)
    assert evaluation.overlapping == 2 and evaluation.recall_overlapping == pytest.approx(0.5)
    assert evaluation.to_dict()["recall_overlapping"] == 0.5
    hidden_partner = ImageResult(pair, pair[1:], np.array([0.9]), truth_ignore=np.array([True, False]))
    evaluation = evaluate([hidden_partner])
    assert evaluation.overlapping == 1 and evaluation.recall_overlapping == 1.0
    alone = evaluate([ImageResult(apart, apart, np.array([0.9]))])
    assert alone.overlapping == 0 and alone.recall_overlapping is None
