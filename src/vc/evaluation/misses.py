"""Why people are missed: a detector's errors on real frames at its operating point, sorted by kind (numpy only).

The analysis behind ``vc-eval``'s ``misses.json`` and ``misses.png``, and how progress on real-frame accuracy is
read. Boxes are [x0, y0, x1, y1] in frame pixels; matching is :func:`vc.evaluation.metrics.evaluate`'s.

1. The operating point is the score threshold of best F1 along the precision-recall curve; only detections at
   or above it are kept.
2. Every ground-truth person is then one of:

   * **found**: matched by a kept detection at IoU >= 0.5;
   * **near miss**: not found, but a kept detection overlaps it by IoU in [:data:`NEAR_IOU`, 0.5): the person was
     seen and the box is wrong. Its error is measured against that detection (the nearest): width and height
     ratios (detection over truth) and the offset of the box centres in truth widths and heights. Whether that
     detection found somebody else (a neighbour's box reaching over) or nobody (a misplaced box) is kept too;
   * **missed**: no kept detection overlaps it by IoU >= :data:`NEAR_IOU`.

3. Every kept detection that matches nobody is a false positive of one kind, tested in this order:

   * **duplicate**: overlaps a found person by IoU >= 0.5 (a second detection of someone already found);
   * **merged**: its box holds the box centres of two or more people (one box over a group);
   * **misplaced**: overlaps one person by IoU >= :data:`NEAR_IOU` (the other side of a near miss);
   * **outside the annotated area**: its foot point lies outside the area the ground truth's people stand in
     (:mod:`vc.evaluation.annotated_area`): often a person the annotation leaves out, which the plain AP50 still
     counts against the detector;
   * **background**: none of these (nobody there, or a person too far off to count).

4. Recall is broken down by group (a person whose box overlaps another's by IoU >=
   :data:`~vc.evaluation.metrics.GROUP_IOU`), person height (:data:`HEIGHT_BINS`), region (the region whose
   owned image area holds the person's foot point, the bottom centre of the box, as the runtime assigns
   detections) and, when the frame's size is given, the frame's edge: a person whose box reaches within
   :data:`CUT_PX` of an edge is **cut by the frame** (annotators clip the box there; people walking in or out),
   the others by how far their box stays from the nearest edge, in their own heights (:data:`EDGE_BINS`).
5. Frames are ranked by their errors (misses, near misses and false positives) for a contact sheet of the worst.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from vc.deploy.areas import in_area
from vc.deploy.boxes import box_iou, foot_points
from vc.evaluation.annotated_area import AnnotatedArea
from vc.evaluation.metrics import IOU_THRESHOLD, Evaluation, ImageResult, evaluate, grouped

#: A detection overlapping a person by at least this IoU (and less than 0.5) makes the person a near miss.
NEAR_IOU = 0.3
#: Ground-truth person heights (px) over which recall is broken down.
HEIGHT_BINS = (0, 60, 80, 100, 10_000)
#: A ground-truth box within this many pixels of a frame edge is cut by the frame (annotators clip boxes to it).
CUT_PX = 2.0
#: Distances of an uncut box to the nearest frame edge, in the person's heights, over which recall is broken down.
EDGE_BINS = (0.0, 0.5, 2.0, float("inf"))
CUT_BY_THE_FRAME = "cut by the frame"
OUTCOMES = ("found", "near miss", "missed")
OUTSIDE_ANNOTATED_AREA = "outside the annotated area"
FALSE_POSITIVE_KINDS = ("duplicate", "merged", "misplaced", OUTSIDE_ANNOTATED_AREA, "background")


@dataclass(frozen=True)
class PersonOutcome:
    """One ground-truth person at the operating point."""

    frame: int
    box: np.ndarray  # (4,) the ground-truth box
    outcome: str  # one of OUTCOMES
    best_iou: float  # with any kept detection
    grouped: bool  # overlaps another ground-truth person by IoU >= GROUP_IOU
    region: str | None  # whose owned area holds the foot point; None outside every region or without regions
    nearest: np.ndarray | None = None  # (4,) the kept detection of best IoU, for near misses
    nearest_found_another: bool = False  # that detection is another person's match
    edge_px: float | None = None  # the box's distance to the nearest frame edge (None: the frame's size unknown)
    identity: int | None = None  # the ground truth's id for the person (None: not given, or MOT's -1, unknown)

    @property
    def height(self) -> float:
        return float(self.box[3] - self.box[1])

    def box_error(self) -> dict | None:
        """A near miss's box against the truth: width and height ratios, centre offsets in truth widths and
        heights (+: the detection is right of / below the person)."""
        if self.nearest is None:
            return None
        truth_size, detected_size = self.box[2:] - self.box[:2], self.nearest[2:] - self.nearest[:2]
        offset = ((self.nearest[:2] + self.nearest[2:]) - (self.box[:2] + self.box[2:])) / 2 / truth_size
        return {"width_ratio": float(detected_size[0] / truth_size[0]),
                "height_ratio": float(detected_size[1] / truth_size[1]),
                "x_offset": float(offset[0]), "y_offset": float(offset[1])}

    def to_dict(self) -> dict:
        result = {"frame": self.frame, "box": [round(float(v), 1) for v in self.box], "outcome": self.outcome,
                  "best_iou": round(self.best_iou, 3), "grouped": self.grouped, "region": self.region}
        if self.edge_px is not None:
            result["edge_px"] = round(self.edge_px, 1)
        if self.identity is not None:
            result["identity"] = self.identity
        error = self.box_error()
        if error is not None:
            result.update({key: round(value, 3) for key, value in error.items()},
                          nearest=[round(float(v), 1) for v in self.nearest],
                          nearest_found_another=self.nearest_found_another)
        return result


@dataclass(frozen=True)
class FalsePositive:
    frame: int
    box: np.ndarray  # (4,)
    score: float
    kind: str  # one of FALSE_POSITIVE_KINDS

    def to_dict(self) -> dict:
        return {"frame": self.frame, "box": [round(float(v), 1) for v in self.box], "score": round(self.score, 4),
                "kind": self.kind}


def _rate(found: np.ndarray) -> dict:
    return {"people": int(len(found)), "recall": round(float(np.mean(found)), 4) if len(found) else None}


def _quartiles(values: Sequence[float]) -> dict | None:
    if not len(values):
        return None
    low, median, high = np.percentile(values, [25, 50, 75])
    return {"median": round(float(median), 3), "q1": round(float(low), 3), "q3": round(float(high), 3)}


@dataclass(frozen=True)
class MissAnalysis:
    """Every person and false positive of a detector's operating point (see the module docstring)."""

    score_threshold: float
    precision: float
    recall: float
    people: list[PersonOutcome]
    false_positives: list[FalsePositive]

    @property
    def f1(self) -> float:
        return 2 * self.precision * self.recall / max(self.precision + self.recall, 1e-9)

    def _found_where(self, selected: Sequence[bool]) -> np.ndarray:
        """Whether each selected person was found."""
        return np.array([person.outcome == "found" for person, chosen in zip(self.people, selected, strict=True)
                         if chosen], bool)

    def recall_by_height(self) -> dict:
        heights = np.array([person.height for person in self.people])
        rates = {}
        for low, high in zip(HEIGHT_BINS[:-1], HEIGHT_BINS[1:], strict=True):
            found = self._found_where((heights >= low) & (heights < high))
            if len(found):
                rates[f"{low}-{high} px" if high < HEIGHT_BINS[-1] else f">= {low} px"] = _rate(found)
        return rates

    def recall_by_group(self) -> dict:
        in_group = np.array([person.grouped for person in self.people], bool)
        return {label: _rate(found) for label, selected in (("apart", ~in_group), ("overlapping another", in_group))
                if len(found := self._found_where(selected))}

    def recall_by_region(self) -> dict:
        regions = [person.region for person in self.people]
        names = sorted({name for name in regions if name is not None})
        rates = {name: _rate(self._found_where([region == name for region in regions])) for name in names}
        outside = self._found_where([region is None for region in regions])
        if len(outside) and names:
            rates["outside every region"] = _rate(outside)
        return rates

    def recall_by_edge(self) -> dict:
        """Recall of the people cut by the frame, and of the others by their distance to the nearest edge in their
        own heights (:data:`EDGE_BINS`); empty when the frame's size was not given."""
        if any(person.edge_px is None for person in self.people):
            return {}
        cut = np.array([person.edge_px <= CUT_PX for person in self.people], bool)
        heights = np.array([max(person.height, 1.0) for person in self.people])
        distance = np.array([person.edge_px for person in self.people]) / heights
        rates = {CUT_BY_THE_FRAME: cut}
        for low, high in zip(EDGE_BINS[:-1], EDGE_BINS[1:], strict=True):
            label = f"{low:g}-{high:g} heights from an edge" if np.isfinite(high) else f">= {low:g} heights"
            rates[label] = ~cut & (distance >= low) & (distance < high)
        return {label: _rate(found) for label, selected in rates.items() if len(found := self._found_where(selected))}

    def outcomes(self, grouped: bool | None = None) -> dict[str, int]:
        """People per outcome, of all people or of those (not) in a group."""
        return {outcome: sum(person.outcome == outcome and grouped in (None, person.grouped)
                             for person in self.people) for outcome in OUTCOMES}

    def false_positive_kinds(self) -> dict[str, int]:
        return {kind: sum(fp.kind == kind for fp in self.false_positives) for kind in FALSE_POSITIVE_KINDS}

    def near_miss_errors(self) -> dict:
        """Quartiles of the near misses' box errors, and how many were a neighbour's box."""
        errors = [person.box_error() for person in self.people if person.outcome == "near miss"]
        result = {key: _quartiles([error[key] for error in errors])
                  for key in ("width_ratio", "height_ratio", "x_offset", "y_offset")}
        result["abs_x_offset"] = _quartiles([abs(error["x_offset"]) for error in errors])
        result["neighbour_box"] = sum(person.nearest_found_another for person in self.people
                                      if person.outcome == "near miss")
        return result

    def frame_errors(self) -> dict[int, int]:
        """Errors per frame (people not found plus false positives), every frame with a person or a detection."""
        errors: dict[int, int] = {}
        for person in self.people:
            errors[person.frame] = errors.get(person.frame, 0) + (person.outcome != "found")
        for fp in self.false_positives:
            errors[fp.frame] = errors.get(fp.frame, 0) + 1
        return errors

    def worst_frames(self, count: int) -> list[int]:
        """The ``count`` frames with the most errors (earlier frames first among equals), frames without errors
        left out."""
        ranked = sorted(((-errors, frame) for frame, errors in self.frame_errors().items() if errors))
        return [frame for _, frame in ranked[:count]]

    def summary(self) -> dict:
        """The operating point in a few numbers (what ``metrics.json`` keeps)."""
        return {"score_threshold": round(self.score_threshold, 4), "precision": round(self.precision, 4),
                "recall": round(self.recall, 4), "f1": round(self.f1, 4),
                "false_positives": len(self.false_positives), "missed": len(self.people) - self.outcomes()["found"],
                "outcomes": self.outcomes(), "recall_by_height": self.recall_by_height(),
                "recall_by_overlap": self.recall_by_group(), "recall_by_region": self.recall_by_region(),
                **({"recall_by_edge": edge} if (edge := self.recall_by_edge()) else {})}

    def to_dict(self) -> dict:
        errors = self.frame_errors()
        return {**self.summary(),
                "outcomes_by_overlap": {"apart": self.outcomes(False), "overlapping another": self.outcomes(True)},
                "near_miss_box_errors": self.near_miss_errors(),
                "false_positive_kinds": self.false_positive_kinds(),
                "worst_frames": [{"frame": frame, "errors": errors[frame]} for frame in self.worst_frames(10)],
                "people": [person.to_dict() for person in self.people if person.outcome != "found"],
                "false_positive_list": [fp.to_dict() for fp in self.false_positives]}


@dataclass(frozen=True)
class OperatingPoint:
    """A detector's detections at its best-F1 score threshold, and whom they match in each image."""

    evaluation: Evaluation
    index: int  # along the ranked detections
    kept: list[np.ndarray]  # per image: indices of the detections at or above the threshold
    matches: list[dict[int, int]]  # per image: ground-truth index -> index into that image's kept detections

    @property
    def threshold(self) -> float:
        return float(self.evaluation.scores[self.index])


def operating_point(images: Sequence[ImageResult]) -> OperatingPoint | None:
    """The score threshold of best F1 over ``images`` and the matches of the detections kept there (None without
    detections). Matching is :func:`vc.evaluation.metrics.evaluate`'s, image by image."""
    evaluation = evaluate(list(images))
    if not len(evaluation.scores):
        return None
    f1 = 2 * evaluation.precision * evaluation.recall / np.maximum(evaluation.precision + evaluation.recall, 1e-9)
    best = int(np.argmax(f1))
    threshold = evaluation.scores[best]
    kept, matches = [], []
    for image in images:
        keep = np.nonzero(image.scores >= threshold)[0]
        pairs = evaluate([ImageResult(image.truth_boxes, image.boxes[keep], image.scores[keep],
                                      truth_ignore=image.truth_ignore)]).matches[0]
        kept.append(keep)
        matches.append(dict(pairs))
    return OperatingPoint(evaluation, best, kept, matches)


def _false_positive_kind(detection: np.ndarray, truth: np.ndarray, overlaps: np.ndarray, found: np.ndarray,
                         annotated: bool) -> str:
    """``overlaps``: this detection's IoU with each ground-truth box; ``found``: which of them are matched;
    ``annotated``: whether its feet stand in the annotated area."""
    if np.any(found & (overlaps >= IOU_THRESHOLD)):
        return "duplicate"
    centres = (truth[:, :2] + truth[:, 2:]) / 2
    inside = np.all((centres >= detection[:2]) & (centres <= detection[2:]), axis=1)
    if inside.sum() >= 2:
        return "merged"
    if np.any(overlaps >= NEAR_IOU):
        return "misplaced"
    return "background" if annotated else OUTSIDE_ANNOTATED_AREA


def analyse_misses(images: Sequence[ImageResult], frames: Sequence[int],
                   region_of: Callable[[np.ndarray], list[str | None]] | None = None,
                   annotated_area: AnnotatedArea | None = None,
                   frame_size: tuple[int, int] | None = None,
                   identities: Sequence[np.ndarray] | None = None) -> MissAnalysis | None:
    """The operating point of ``images`` (one per frame number in ``frames``), every person and false positive
    sorted by kind. ``region_of`` maps foot points (N, 2) to region names (None: outside every region);
    ``annotated_area``: where the ground truth annotates people (None: everywhere); ``frame_size`` (width, height):
    the frames', for recall by the frame's edge (None: not broken down); ``identities``: per image, the ground
    truth's person ids in the order of its boxes, to follow people over the frames (:mod:`vc.evaluation.arrivals`).
    None when there are no detections."""
    point = operating_point(images)
    if point is None:
        return None
    people: list[PersonOutcome] = []
    false_positives: list[FalsePositive] = []
    if identities is None:
        identities = [None] * len(images)
    for image, frame, keep, matched_truth, ids in zip(images, frames, point.kept, point.matches, identities,
                                                      strict=True):
        boxes, scores = image.boxes[keep], image.scores[keep]
        truth = np.asarray(image.truth_boxes, np.float64).reshape(-1, 4)
        matched_detections = set(matched_truth.values())
        found = np.isin(np.arange(len(truth)), list(matched_truth))
        iou = box_iou(truth, boxes)  # (people, detections)
        regions = region_of(foot_points(truth)) if region_of is not None and len(truth) else [None] * len(truth)
        in_group = grouped(truth)
        ignored = image.ignored()
        annotated = annotated_area.contains(boxes) if annotated_area is not None else np.ones(len(boxes), bool)
        edges = _edge_distances(truth, frame_size) if frame_size is not None else [None] * len(truth)
        for index, box in enumerate(truth):
            if ignored[index]:
                continue
            overlaps = iou[index] if len(boxes) else np.zeros(0)
            best_iou = float(overlaps.max(initial=0.0))
            if found[index]:
                outcome, nearest, another = "found", None, False
            elif best_iou >= NEAR_IOU:
                nearest_index = int(np.argmax(overlaps))
                outcome, nearest, another = "near miss", boxes[nearest_index], nearest_index in matched_detections
            else:
                outcome, nearest, another = "missed", None, False
            people.append(PersonOutcome(int(frame), box, outcome, best_iou, bool(in_group[index]), regions[index],
                                        nearest, another, edges[index],
                                        None if ids is None or ids[index] < 0 else int(ids[index])))
        for detection, (box, score) in enumerate(zip(boxes, scores, strict=True)):
            if detection in matched_detections:
                continue
            overlaps = iou[:, detection] if len(truth) else np.zeros(0)
            if np.any(ignored & (overlaps >= IOU_THRESHOLD)):
                continue  # someone we do not ask for, as in the AP
            kind = _false_positive_kind(box, truth, overlaps, found, bool(annotated[detection]))
            false_positives.append(FalsePositive(int(frame), box, float(score), kind))
    return MissAnalysis(point.threshold, float(point.evaluation.precision[point.index]),
                        float(point.evaluation.recall[point.index]), people, false_positives)


def _edge_distances(boxes: np.ndarray, frame_size: tuple[int, int]) -> list[float]:
    """Each box's distance (px) to the nearest edge of a ``frame_size`` (width, height) frame; 0 or less when it
    reaches or crosses one."""
    width, height = frame_size
    return [float(value) for value in np.min(np.stack(
        [boxes[:, 0], boxes[:, 1], width - boxes[:, 2], height - boxes[:, 3]]), axis=0)] if len(boxes) else []


def region_lookup(areas: Mapping[str, dict]) -> Callable[[np.ndarray], list[str | None]]:
    """A ``region_of`` for :func:`analyse_misses` from regions' owned image areas (GeoJSON, as a bundle's manifest
    holds them): the first region holding each point."""
    def region_of(points: np.ndarray) -> list[str | None]:
        names: list[str | None] = [None] * len(points)
        for name, area in areas.items():
            for index in np.nonzero(in_area(points, area))[0]:
                names[index] = names[index] or name
        return names
    return region_of
