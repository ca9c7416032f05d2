"""People coming into view (vc.evaluation.arrivals): each newcomer followed from their first scored frame to the frame
the detector finds them, those walking in at an edge apart from those appearing inside the view."""

from __future__ import annotations

import numpy as np
import pytest

from vc.evaluation.arrivals import APPEARING_INSIDE, WALKING_IN, arrivals, summarise
from vc.evaluation.metrics import ImageResult
from vc.evaluation.misses import analyse_misses
from vc.evaluation.plots import plot_miss_analysis

FRAME_SIZE = (640, 480)
STAYING = [300, 100, 320, 160]  # there from the first frame, always found
WALKER_CUT, WALKER_WHOLE = [0, 100, 8, 160], [0, 100, 20, 160]  # walks in at the left edge, found once whole
APPEARING = [100, 300, 120, 360]  # appears in the middle of the view and is found at once
UNSEEN = [500, 424, 520, 479]  # walks in at the bottom edge and is never found


def _frame(people: list[tuple[int, list[float], bool]]) -> tuple[ImageResult, np.ndarray]:
    """(identity, box, detected) per person -> the frame's image result (detections exactly on the found people's
    boxes) and its identities."""
    truth = np.array([box for _, box, _ in people], float).reshape(-1, 4)
    found = np.array([box for _, box, detected in people if detected], float).reshape(-1, 4)
    return (ImageResult(truth_boxes=truth, boxes=found, scores=np.linspace(0.9, 0.8, len(found))),
            np.array([identity for identity, _, _ in people], int))


@pytest.fixture(scope="module")
def misses():
    frames = {1: [(1, STAYING, True)],
              2: [(1, STAYING, True), (2, WALKER_CUT, False)],
              3: [(1, STAYING, True), (2, WALKER_CUT, False), (3, APPEARING, True), (4, UNSEEN, False)],
              4: [(1, STAYING, True), (2, WALKER_WHOLE, True), (3, APPEARING, True), (4, UNSEEN, False)]}
    images, identities = zip(*(_frame(people) for people in frames.values()), strict=True)
    return analyse_misses(list(images), list(frames), frame_size=FRAME_SIZE, identities=list(identities))


@pytest.fixture(scope="module")
def followed(misses):
    return arrivals(misses.people, [1, 2, 3, 4])


def test_newcomers_are_followed_from_their_first_frame_to_the_frame_they_are_found(followed):
    by_identity = {arrival.identity: arrival for arrival in followed}
    assert set(by_identity) == {2, 3, 4}  # 1 was there when scoring began
    assert by_identity[2].walked_in and by_identity[2].edge_heights == 0.0
    assert (by_identity[2].first_frame, by_identity[2].found_frame, by_identity[2].delay_frames) == (2, 4, 2)
    assert not by_identity[3].walked_in and by_identity[3].delay_frames == 0
    assert by_identity[4].walked_in and by_identity[4].found_frame is None and by_identity[4].delay_frames is None


def test_summary_counts_each_kind_and_gives_seconds_given_the_frame_rate(followed):
    summary = summarise(followed, fps=10.0)
    assert summary[WALKING_IN] == {"people": 2, "found_in_first_frame": 0, "never_found": 1,
                                   "median_delay_frames": 2.0, "found_within": {"seconds": 1.0, "people": 1},
                                   "median_delay_s": 0.2}
    assert summary[APPEARING_INSIDE]["people"] == 1 and summary[APPEARING_INSIDE]["found_in_first_frame"] == 1
    # Two frames at 1 frame/s are over the second: found, but not promptly.
    assert summarise(followed, fps=1.0)[WALKING_IN]["found_within"]["people"] == 0
    assert "median_delay_s" not in summarise(followed, fps=None)[WALKING_IN]


def test_the_miss_figure_draws_the_arrivals(misses, followed, tmp_path):
    plot_miss_analysis(misses, tmp_path / "misses.png", "test", summarise(followed, fps=10.0))
    assert (tmp_path / "misses.png").stat().st_size > 10_000


def test_people_without_identities_are_not_followed():
    image, _ = _frame([(1, STAYING, True)])
    later, _ = _frame([(1, STAYING, True), (2, APPEARING, True)])
    misses = analyse_misses([image, later], [1, 2], frame_size=FRAME_SIZE)
    assert all(person.identity is None for person in misses.people)
    assert arrivals(misses.people, [1, 2]) == []
    # MOT files mark an unknown id -1: such people are not one person followed across the frames.
    unknown = analyse_misses([image, later], [1, 2], frame_size=FRAME_SIZE,
                             identities=[np.array([1]), np.array([1, -1])])
    assert arrivals(unknown.people, [1, 2]) == []
