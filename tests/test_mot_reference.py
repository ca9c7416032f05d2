"""vc.evaluation.tracks against py-motmetrics, the field's reference for CLEAR MOT and IDF1: the same frames give the
same counts (misses, false positives, identity switches, matches, IDTP) and the same MOTA, MOTP and IDF1.

Boxes have whole-pixel corners, so the [x, y, w, h] boxes motmetrics takes hold exactly the same numbers and both
sides compute bit-identical IoUs; near-ties and exact ties in the matching are then the same for both.
See docs/decisions/0012-mot-metrics.md.
"""

from __future__ import annotations

import math

import motmetrics as mm
import numpy as np
import pytest
from hard_cases.hard_case_settings import PROPERTY
from hypothesis import given
from hypothesis import strategies as st

from vc.evaluation.tracks import IOU_THRESHOLD, FrameTracks, TrackAccuracy, track_accuracy

SCORE_THRESHOLD = 0.5
METRICS = ["num_objects", "num_predictions", "num_matches", "num_switches", "num_misses", "num_false_positives",
           "idtp", "mota", "motp", "idf1"]


def _xywh(boxes: np.ndarray) -> np.ndarray:
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    return np.column_stack([boxes[:, :2], boxes[:, 2:] - boxes[:, :2]])


def _reference(frames: list[FrameTracks], score_threshold: float) -> dict:
    """motmetrics' summary of the same frames, hypotheses under the score threshold left out as tracks.py does.

    The distance is motmetrics' own IoU distance at ``max_iou = 1 - IOU_THRESHOLD``, written out as
    ``distances.iou_matrix`` computes it: that function calls ``np.asfarray``, which NumPy 2 removed. motmetrics
    takes the first assignment solver it finds installed (lapsolver, lap, then scipy); the solver decides exact ties,
    so the test fixes scipy's, the one tracks.py uses."""
    accumulator = mm.MOTAccumulator(auto_id=True)
    with mm.lap.set_default_solver("scipy"):
        for frame in frames:
            keep = np.asarray(frame.scores) >= score_threshold
            boxes, tracks = np.asarray(frame.boxes).reshape(-1, 4)[keep], np.asarray(frame.tracks)[keep]
            distance = 1.0 - mm.distances.boxiou(_xywh(frame.truth_boxes)[:, None], _xywh(boxes)[None, :])
            distance = np.where(distance > 1.0 - IOU_THRESHOLD, np.nan, distance)
            accumulator.update(np.asarray(frame.truth_ids), tracks, distance)
        return mm.metrics.create().compute(accumulator, metrics=METRICS, return_dataframe=False)


def _assert_agree(frames: list[FrameTracks], score_threshold: float = SCORE_THRESHOLD) -> TrackAccuracy:
    ours, reference = track_accuracy(frames, score_threshold), _reference(frames, score_threshold)
    counts = {"truth": ours.truth, "hypotheses": ours.hypotheses, "matches": ours.matches,
              "id_switches": ours.id_switches, "misses": ours.misses, "false_positives": ours.false_positives,
              "idtp": ours.idtp}
    # motmetrics counts a switch apart from the matches; tracks.py's matches include the switches.
    expected = {"truth": reference["num_objects"], "hypotheses": reference["num_predictions"],
                "matches": reference["num_matches"] + reference["num_switches"],
                "id_switches": reference["num_switches"], "misses": reference["num_misses"],
                "false_positives": reference["num_false_positives"], "idtp": reference["idtp"]}
    assert counts == {key: int(value) for key, value in expected.items()}
    # motmetrics' MOTP is the mean IoU distance, 1 - IoU; tracks.py reports the mean IoU. Without people or
    # matches tracks.py has no ratio (None) where motmetrics divides by zero (nan or inf).
    for ours_value, reference_value in ((ours.mota, reference["mota"]), (ours.idf1, reference["idf1"]),
                                        (None if ours.motp is None else 1.0 - ours.motp, reference["motp"])):
        if ours_value is None:
            assert not math.isfinite(reference_value)
        else:
            assert ours_value == pytest.approx(reference_value, abs=1e-9, rel=0)
    return ours


def _frame(truth: list[tuple[int, list[float]]], hypotheses: list[tuple[int, list[float], float]]) -> FrameTracks:
    return FrameTracks(np.array([box for _, box in truth], np.float64).reshape(-1, 4),
                       np.array([person for person, _ in truth], int),
                       np.array([box for _, box, _ in hypotheses], np.float64).reshape(-1, 4),
                       np.array([score for _, _, score in hypotheses], np.float64),
                       np.array([track for track, _, _ in hypotheses], int))


def _at(x: float) -> list[float]:
    """A 10 x 20 box at x."""
    return [x, 0.0, x + 10.0, 20.0]


A, B, C = _at(0), _at(30), _at(60)
NEAR_A = _at(2)  # IoU with A: 8 / 12


HAND_MADE = {
    "perfect": [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.9)])] * 3,
    "switch": [_frame([(1, A)], [(7, A, 0.9)])] * 2 + [_frame([(1, A)], [(8, A, 0.9)])] * 2,
    "exchange": [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.9)])] * 2
    + [_frame([(1, A), (2, B)], [(8, A, 0.9), (7, B, 0.9)])] * 2,
    # lost for two frames, then found again by the same track (no switch) or by a new one (a switch)
    "fragment_same_track": [_frame([(1, A)], [(7, A, 0.9)]), _frame([(1, A)], []), _frame([(1, A)], []),
                            _frame([(1, A)], [(7, A, 0.9)])],
    "fragment_new_track": [_frame([(1, A)], [(7, A, 0.9)]), _frame([(1, A)], []), _frame([(1, A)], [(9, A, 0.9)])],
    "false_positive": [_frame([(1, A)], [(7, A, 0.9), (8, C, 0.9)])] * 2,
    "miss": [_frame([(1, A), (2, B)], [(7, A, 0.9)])] * 2,
    "below_score_threshold": [_frame([(1, A), (2, B)], [(7, A, 0.9), (8, B, 0.3)]),
                              _frame([(1, A)], [(7, A, 0.9), (9, B, 0.9)])],
    "under_iou_threshold": [_frame([(1, A)], [(7, _at(4), 0.9)])],  # IoU 6 / 14
    "crossing": [_frame([(1, _at(x)), (2, _at(40 - x))], [(7, _at(x), 0.9), (8, _at(40 - x), 0.9)])
                 for x in range(0, 41, 5)],
    "crossing_with_swap": [_frame([(1, _at(x)), (2, _at(40 - x))], [(7, _at(min(x, 40 - x)), 0.9),
                                                                    (8, _at(max(x, 40 - x)), 0.9)])
                           for x in range(0, 41, 5)],
    "empty_frames": [_frame([], []), _frame([(1, A)], [(7, A, 0.9)]), _frame([], []), _frame([(1, A)], [(7, A, 0.9)])],
    "only_false_positives": [_frame([], [(7, A, 0.9)])] * 2,
    "nothing": [_frame([], [])] * 2,
    "no_frames": [],
    "track_starts_late": [_frame([(1, A), (2, B)], [(7, A, 0.9)])] * 3 + [_frame([(1, A), (2, B)],
                                                                               [(7, A, 0.9), (8, B, 0.9)])] * 3,
    "person_leaves_and_returns": [_frame([(1, A)], [(7, A, 0.9)]), _frame([], [(7, C, 0.9)]),
                                  _frame([(1, A)], [(7, A, 0.9)])],
    # track 7 still overlaps person 1 at IoU >= 0.5: the match is kept though track 8 overlaps them better
    "kept_match": [_frame([(1, A)], [(7, A, 0.9)]), _frame([(1, A)], [(7, NEAR_A, 0.9), (8, A, 0.8)])],
    # person 2 took over track 7 while person 1 was away; both come back under track 7's box, which can match one
    "kept_track_claimed_twice": [_frame([(1, A)], [(7, A, 0.9)]), _frame([(2, A)], [(7, A, 0.9)]),
                                 _frame([(1, A), (2, NEAR_A)], [(7, A, 0.9), (8, NEAR_A, 0.9)])],
    # two pairs at IoU 9/11 hold more IoU than three at 7/13, but the three pairs leave nobody missed
    "more_matches_over_more_iou": [_frame([(1, _at(0)), (2, _at(4)), (3, _at(8))],
                                          [(7, _at(3), 0.9), (8, _at(7), 0.9), (9, _at(11), 0.9)])],
}


@pytest.mark.parametrize("name", sorted(HAND_MADE))
def test_hand_made_cases_agree_with_motmetrics(name):
    _assert_agree(HAND_MADE[name])


def test_the_hand_made_cases_mean_what_they_say():
    assert _assert_agree(HAND_MADE["switch"]).id_switches == 1
    assert _assert_agree(HAND_MADE["exchange"]).id_switches == 2
    assert _assert_agree(HAND_MADE["fragment_same_track"]).id_switches == 0
    assert _assert_agree(HAND_MADE["fragment_new_track"]).id_switches == 1
    assert _assert_agree(HAND_MADE["crossing_with_swap"]).id_switches == 2
    assert _assert_agree(HAND_MADE["kept_match"]).id_switches == 0
    claimed = _assert_agree(HAND_MADE["kept_track_claimed_twice"])
    assert claimed.matches == 4 and claimed.misses == 0 and claimed.false_positives == 0
    assert _assert_agree(HAND_MADE["more_matches_over_more_iou"]).matches == 3


# Random scenes. Walking: up to four people moving a few pixels a frame, tracks that follow them with a jitter, drop
# out, change number, and false positives. Crowded: people and tracks drawn afresh each frame on a few neighbouring
# places, so that a box overlaps several others, tracks hop between people and the assignment has exact ties.
# Every corner is a whole pixel.
_BOX = st.tuples(st.integers(0, 40), st.integers(0, 10), st.integers(2, 12), st.integers(4, 20))
_STEP = st.tuples(st.integers(-3, 3), st.integers(-1, 1))
_JITTER = st.tuples(*[st.integers(-2, 2)] * 4)
_SCORE = st.sampled_from([0.3, 0.9])


@st.composite
def _walking(draw) -> list[FrameTracks]:
    people = draw(st.lists(_BOX, max_size=4))
    frames = []
    for _ in range(draw(st.integers(1, 8))):
        truth, hypotheses, used_tracks = [], [], set()
        for person, (x, y, w, h) in enumerate(people):
            dx, dy = draw(_STEP)
            people[person] = (x + dx, y + dy, w, h)
            if not draw(st.booleans()) and draw(st.booleans()):
                continue  # not in this frame
            box = [x + dx, y + dy, x + dx + w, y + dy + h]
            truth.append((person, box))
            track = draw(st.integers(0, 5))
            if draw(st.integers(0, 3)) and track not in used_tracks:
                used_tracks.add(track)
                jitter = draw(_JITTER)
                hypotheses.append((track, [box[0] + jitter[0], box[1] + jitter[1], box[2] + max(jitter[2], 1 - w),
                                           box[3] + max(jitter[3], 1 - h)], draw(_SCORE)))
        for x, y, w, h in draw(st.lists(_BOX, max_size=2)):
            track = draw(st.integers(0, 7))
            if track not in used_tracks:
                used_tracks.add(track)
                hypotheses.append((track, [x, y, x + w, y + h], draw(_SCORE)))
        order = draw(st.permutations(range(len(hypotheses))))
        frames.append(_frame(truth, [hypotheses[i] for i in order]))
    return frames


_PLACE = st.builds(lambda x, w: [x, 0, x + w, 20], st.sampled_from([0, 1, 2, 4, 6, 30]), st.sampled_from([10, 12]))
_CROWDED_FRAME = st.builds(
    _frame, st.lists(st.tuples(st.integers(0, 3), _PLACE), min_size=1, max_size=4, unique_by=lambda person: person[0]),
    st.lists(st.tuples(st.integers(0, 4), _PLACE, _SCORE), min_size=1, max_size=5, unique_by=lambda track: track[0]))


@PROPERTY
@given(_walking())
def test_walking_scenes_agree_with_motmetrics(frames):
    _assert_agree(frames)


@PROPERTY
@given(st.lists(_CROWDED_FRAME, min_size=2, max_size=6))
def test_crowded_scenes_agree_with_motmetrics(frames):
    _assert_agree(frames)
