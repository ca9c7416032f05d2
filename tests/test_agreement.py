"""Pose agreement with a reference pose model (vc.evaluation.agreement): the proxy for pose on real people."""

from __future__ import annotations

import numpy as np
import pytest

from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.metrics import ImageResult

TRUTH = np.array([[0, 0, 20, 80], [100, 0, 120, 80]], float)  # 80 px tall: a head size is 10 px


def _keypoints(x: float, confidence: float = 0.9) -> np.ndarray:
    keypoints = np.zeros((17, 3))
    keypoints[:, 0], keypoints[:, 1], keypoints[:, 2] = x, np.linspace(5, 75, 17), confidence
    return keypoints


def test_keypoints_agree_within_half_a_head_size_of_the_references_confident_ones():
    reference_keypoints = np.stack([_keypoints(10.0), _keypoints(110.0)])
    reference_keypoints[0, :4, 2] = 0.2  # the reference is unsure of four keypoints: they are not compared
    reference = [ImageResult(TRUTH, TRUTH.copy(), np.array([0.9, 0.8]), keypoints=reference_keypoints)]
    ours = _keypoints(10.0)
    ours[4:8, 0] += 4.9  # within 0.5 head sizes (5 px)
    ours[8:10, 0] += 5.1  # beyond
    # Only the first person is found by both: ours misses the second one.
    candidate = [ImageResult(TRUTH, TRUTH[:1].copy(), np.array([0.7]), keypoints=ours[None])]
    agreement = pose_agreement(candidate, reference)
    assert agreement.people == 1 and agreement.compared.sum() == 13
    assert agreement.overall == pytest.approx(11 / 13)
    per_keypoint = agreement.per_keypoint()
    assert per_keypoint["nose"] is None and per_keypoint["left_shoulder"] == 1.0
    assert per_keypoint["right_elbow"] == 0.0 and per_keypoint["left_wrist"] == 0.0


def test_nobody_found_by_both_has_no_agreement():
    reference = [ImageResult(TRUTH, np.zeros((0, 4)), np.zeros(0), keypoints=np.zeros((0, 17, 3)))]
    candidate = [ImageResult(TRUTH, TRUTH.copy(), np.array([0.9, 0.9]), keypoints=np.zeros((2, 17, 3)))]
    agreement = pose_agreement(candidate, reference)
    assert agreement.people == 0 and agreement.overall is None
    assert agreement.to_dict()["overall"] is None
    with pytest.raises(ValueError, match="same frames"):
        pose_agreement(candidate, reference * 2)


def test_a_person_facing_the_other_way_counts_as_left_and_right_exchanged():
    reference_keypoints = _keypoints(10.0)
    for left, right in PAIRS:  # a person facing the camera: their left side on the image's right
        reference_keypoints[left, 0], reference_keypoints[right, 0] = 16.0, 4.0
        reference_keypoints[right, 1] = reference_keypoints[left, 1]
    reference = [ImageResult(TRUTH[:1], TRUTH[:1].copy(), np.array([0.9]), keypoints=reference_keypoints[None])]
    ours = swap_pairs(reference_keypoints, [True] * len(PAIRS))  # the same points, read as facing away
    agreement = pose_agreement([ImageResult(TRUTH[:1], TRUTH[:1].copy(), np.array([0.9]), keypoints=ours[None])],
                               reference)
    assert agreement.overall == pytest.approx(1 / 17)  # only the nose, which has no pair
    assert agreement.left_right_swapped == 1 and agreement.overall_if_left_right_matched == 1.0
    assert pose_agreement(reference, reference).left_right_swapped == 0
    assert pose_agreement(reference, reference).to_dict()["overall_if_left_right_matched"] == 1.0


def test_a_shift_shared_by_a_keypoint_shows_as_its_median_offset_in_head_sizes():
    reference_keypoints = np.stack([_keypoints(10.0), _keypoints(110.0)])  # head size 10 px (TRUTH is 80 px tall)
    for left, right in PAIRS:  # pairs side by side, so that reading them exchanged agrees less
        reference_keypoints[:, left, 0] += 6.0
        reference_keypoints[:, right, 0] -= 6.0
    ours = reference_keypoints.copy()
    ours[:, 0, 1] -= 3.0  # the nose read 0.3 head sizes higher on both people
    ours[0, 15, 0] += 2.0  # one left ankle 0.2 to the right, the other where the reference has it: median 0.1
    for left, right in PAIRS:  # the second person read facing the other way: compared in the better order
        ours[1, [left, right]] = ours[1, [right, left]]
    agreement = pose_agreement([ImageResult(TRUTH, TRUTH.copy(), np.array([0.9, 0.8]), keypoints=ours)],
                               [ImageResult(TRUTH, TRUTH.copy(), np.array([0.9, 0.8]), keypoints=reference_keypoints)])
    offsets = agreement.to_dict()["median_offset_head_sizes"]
    assert offsets["nose"] == [0.0, -0.3] and offsets["left_ankle"] == [0.1, 0.0]
    assert offsets["right_knee"] == [0.0, 0.0]
