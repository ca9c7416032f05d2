"""How well the bundle's tracks follow people: CLEAR MOT (MOTA, identity switches; Bernardin and Stiefelhagen,
2008) and IDF1 (Ristani et al., 2016) against the ground truth's own tracks, over the scored frames.

1. Hypotheses are the tracked people kept at the bundle's operating point (the best-F1 score threshold, as in the
   miss analysis), each with its track number; carried people count like seen ones.
2. Per frame, a ground-truth person keeps the track they were last matched to while its box still overlaps theirs
   at IoU >= 0.5 and no one before them in the frame kept it; the other people and boxes are paired one to one
   (Hungarian, scipy), pairs under 0.5 excluded: as many pairs as possible and, among those, the least total
   distance 1 - IoU.
3. A ground-truth person matched to another track than the one they were last matched to is an identity switch.
4. MOTA = 1 - (misses + false positives + switches) / ground-truth people; MOTP is the mean IoU of the matches.
5. IDF1: each ground-truth track is paired with at most one hypothesis track (and each hypothesis track with at
   most one person) so that the frames where the pair overlaps at IoU >= 0.5 are the most (Hungarian); those
   frames are the identity true positives, and IDF1 = 2 IDTP / (ground-truth people + hypotheses).

Frames are those scored: with every 5th frame scored, a switch is counted between scored frames.

These are py-motmetrics' definitions (``MOTAccumulator`` with the IoU distance at ``max_iou=0.5``), exact ties in the
assignment resolved as there: tests/test_mot_reference.py checks that both give the same counts and ratios, and
docs/decisions/0012-mot-metrics.md says why motmetrics is a test dependency only.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from vc.deploy.boxes import box_iou

IOU_THRESHOLD = 0.5


@dataclass(frozen=True)
class FrameTracks:
    """One scored frame: ground-truth boxes (N, 4) with their person ids (N,), and the hypotheses' boxes (M, 4),
    scores (M,) and track numbers (M,)."""

    truth_boxes: np.ndarray
    truth_ids: np.ndarray
    boxes: np.ndarray
    scores: np.ndarray
    tracks: np.ndarray


@dataclass(frozen=True)
class TrackAccuracy:
    truth: int  # ground-truth people over the frames
    hypotheses: int
    matches: int
    misses: int
    false_positives: int
    id_switches: int
    iou_sum: float
    idtp: int

    @property
    def mota(self) -> float | None:
        return 1.0 - (self.misses + self.false_positives + self.id_switches) / self.truth if self.truth else None

    @property
    def motp(self) -> float | None:
        return self.iou_sum / self.matches if self.matches else None

    @property
    def idf1(self) -> float | None:
        total = self.truth + self.hypotheses
        return 2.0 * self.idtp / total if total else None

    def to_dict(self) -> dict:
        def rounded(value: float | None) -> float | None:
            return None if value is None else round(value, 4)

        return {"mota": rounded(self.mota), "idf1": rounded(self.idf1), "motp_iou": rounded(self.motp),
                "id_switches": self.id_switches, "misses": self.misses, "false_positives": self.false_positives,
                "ground_truth": self.truth, "hypotheses": self.hypotheses}


def _frame_matches(iou: np.ndarray, truth_ids: np.ndarray, tracks: np.ndarray,
                   previous: dict[int, int]) -> dict[int, int]:
    """Step 2 for one frame: truth index -> hypothesis index."""
    matches: dict[int, int] = {}
    for truth, person in enumerate(truth_ids):
        if int(person) not in previous:
            continue
        kept = [h for h in np.nonzero(tracks == previous[int(person)])[0] if h not in matches.values()]
        if kept and iou[truth, kept[0]] >= IOU_THRESHOLD:
            matches[truth] = int(kept[0])
    allowed = iou >= IOU_THRESHOLD
    allowed[list(matches), :] = False
    allowed[:, list(matches.values())] = False
    if allowed.any():
        distance = 1.0 - iou
        # A pair that is not allowed costs more than a whole assignment of allowed pairs, so the assignment has the
        # most pairs possible and, among those, the least total distance 1 - IoU. The constant is motmetrics' (the
        # reference, tests/test_mot_reference.py): exact ties then resolve as they do there.
        costly = 2.0 * min(iou.shape) * (distance[allowed].max() + 1.0) + 1.0
        rows, columns = linear_sum_assignment(np.where(allowed, distance, costly))
        for row, column in zip(rows, columns, strict=True):
            if allowed[row, column]:
                matches[int(row)] = int(column)
    return matches


def track_accuracy(frames: Sequence[FrameTracks], score_threshold: float) -> TrackAccuracy:
    """CLEAR MOT and IDF1 of the hypotheses scoring at least ``score_threshold`` (see the module docstring)."""
    truth_count = hypothesis_count = match_count = switches = idtp = 0
    iou_sum = 0.0
    previous: dict[int, int] = {}  # person -> the track they were last matched to
    shared: dict[tuple[int, int], int] = {}  # (person, track) -> frames where they overlap at IoU >= 0.5
    for frame in frames:
        keep = np.asarray(frame.scores) >= score_threshold
        boxes, tracks = np.asarray(frame.boxes).reshape(-1, 4)[keep], np.asarray(frame.tracks)[keep]
        truth_ids = np.asarray(frame.truth_ids).astype(int)
        iou = box_iou(frame.truth_boxes, boxes)
        for truth, hypothesis in zip(*np.nonzero(iou >= IOU_THRESHOLD), strict=True):
            key = (int(truth_ids[truth]), int(tracks[hypothesis]))
            shared[key] = shared.get(key, 0) + 1
        matches = _frame_matches(iou, truth_ids, tracks, previous)
        for truth, hypothesis in matches.items():
            person, track = int(truth_ids[truth]), int(tracks[hypothesis])
            switches += int(person in previous and previous[person] != track)
            previous[person] = track
            iou_sum += float(iou[truth, hypothesis])
        truth_count += len(truth_ids)
        hypothesis_count += len(tracks)
        match_count += len(matches)
    if shared:
        people = sorted({person for person, _ in shared})
        track_numbers = sorted({track for _, track in shared})
        overlap = np.zeros((len(people), len(track_numbers)))
        for (person, track), count in shared.items():
            overlap[people.index(person), track_numbers.index(track)] = count
        rows, columns = linear_sum_assignment(-overlap)
        idtp = int(overlap[rows, columns].sum())
    return TrackAccuracy(truth_count, hypothesis_count, match_count, truth_count - match_count,
                         hypothesis_count - match_count, switches, iou_sum, idtp)
