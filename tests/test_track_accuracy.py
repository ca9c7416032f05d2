"""Track accuracy against ground-truth tracks (vc.evaluation.tracks): CLEAR MOT and IDF1 on hand-made cases."""

from __future__ import annotations

import numpy as np
import pytest

from vc.evaluation.tracks import FrameTracks, track_accuracy

A, B = np.array([0.0, 0.0, 10.0, 20.0]), np.array([30.0, 0.0, 40.0, 20.0])


def _frame(truth: list[tuple[int, np.ndarray]], hypotheses: list[tuple[int, np.ndarray, float]]) -> FrameTracks:
    return FrameTracks(np.array([box for _, box in truth]).reshape(-1, 4), np.array([i for i, _ in truth], int),
                       np.array([box for _, box, _ in hypotheses]).reshape(-1, 4),
                       np.array([score for _, _, score in hypotheses]), np.array([t for t, _, _ in hypotheses], int))


def test_perfect_tracks_score_one():
    frames = [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.9)]) for _ in range(4)]
    accuracy = track_accuracy(frames, 0.5)
    assert accuracy.mota == 1.0 and accuracy.idf1 == 1.0 and accuracy.motp == 1.0 and accuracy.id_switches == 0


def test_two_tracks_exchanging_people_is_two_switches_and_halves_idf1():
    frames = [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.9)]) for _ in range(2)]
    frames += [_frame([(1, A), (2, B)], [(8, A, 0.9), (7, B, 0.9)]) for _ in range(2)]
    accuracy = track_accuracy(frames, 0.5)
    assert accuracy.id_switches == 2 and accuracy.misses == accuracy.false_positives == 0
    assert accuracy.mota == pytest.approx(1 - 2 / 8) and accuracy.idf1 == pytest.approx(0.5)


def test_a_match_is_kept_while_it_overlaps_rather_than_reassigned():
    # Track 8's box overlaps person 1 better in the second frame, but track 7 still overlaps them at IoU >= 0.5.
    shifted = A + [2.0, 0.0, 2.0, 0.0]  # IoU with A: 8 / 12
    frames = [_frame([(1, A)], [(7, A, 0.9)]), _frame([(1, A)], [(7, shifted, 0.9), (8, A, 0.8)])]
    accuracy = track_accuracy(frames, 0.5)
    assert accuracy.id_switches == 0 and accuracy.false_positives == 1


def test_hypotheses_below_the_threshold_and_missed_people_count():
    frames = [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.3)]), _frame([(1, A)], [(7, A, 0.9), (9, B, 0.9)])]
    accuracy = track_accuracy(frames, 0.5)
    assert (accuracy.truth, accuracy.hypotheses, accuracy.misses, accuracy.false_positives) == (3, 3, 1, 1)
    assert accuracy.mota == pytest.approx(1 - 2 / 3) and accuracy.idf1 == pytest.approx(2 * 2 / 6)
    assert track_accuracy([], 0.5).to_dict()["mota"] is None
