"""Accuracy metrics, one implementation for tests, training, benchmarks and ``vc-eval`` (docs/design.md, "Metrics").

* Detection: average precision at IoU 0.5, all-point interpolated (VOC 2010 and later): detections of all
  images sorted by score, each greedily matched to the unmatched ground-truth box of highest IoU >= 0.5 in its
  image; AP is the area under the precision envelope. Ground truth marked ``ignore`` (people too hidden or cut
  off to ask for, as COCO's crowd regions) is neither a miss nor a match: a detection that finds nothing else but
  overlaps one by IoU >= 0.5 is dropped from the ranking. So is a detection marked ``ignore`` (outside the area a
  ground truth annotates) that finds nobody; one that finds somebody counts as usual.
* Pose: PCKh@0.5 over the keypoints of matched people that are labelled (v > 0): correct when within half a head
  size of the truth, the head size being 1/8 of the ground-truth person height in pixels (COCO has no head
  segment; this is the stated stand-in). Also per keypoint.
* Segmentation: mean IoU of matched people's masks.
* People in groups: the recall, over every detection kept, of the people whose box overlaps another person's by
  IoU >= :data:`GROUP_IOU` (side by side, one behind another): what a detector that merges neighbours into one
  peak loses, and what AP over everyone hides (one person in ten on PETS09, where it is the weakest recall).

Boxes are [x0, y0, x1, y1] (outer edges), numpy only: the appliance side may import this.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vc.deploy.boxes import box_iou

IOU_THRESHOLD = 0.5
#: Ground-truth people overlapping another by at least this IoU count as "in a group" (groups, occlusion).
GROUP_IOU = 0.1
PCKH_FRACTION = 0.5
HEAD_FRACTION_OF_HEIGHT = 1.0 / 8.0


@dataclass
class ImageResult:
    """One image's ground truth and detections."""

    truth_boxes: np.ndarray  # (N, 4)
    boxes: np.ndarray  # (M, 4)
    scores: np.ndarray  # (M,)
    truth_keypoints: np.ndarray | None = None  # (N, 17, 3) x, y, v
    keypoints: np.ndarray | None = None  # (M, 17, 2+)
    truth_masks: list[np.ndarray] | None = None  # N boolean masks
    masks: list[np.ndarray] | None = None  # M boolean masks (same shape as the truth)
    truth_ignore: np.ndarray | None = None  # (N,) bool: neither a miss nor a match (see the module docstring)
    #: (M,) bool: detections that count when they match someone and are not held against the detector when they
    #: match nobody (outside the area a ground truth annotates: vc.evaluation.annotated_area).
    detection_ignore: np.ndarray | None = None

    def ignored(self) -> np.ndarray:
        return np.zeros(len(self.truth_boxes), bool) if self.truth_ignore is None else np.asarray(self.truth_ignore)

    def detections_ignored(self) -> np.ndarray:
        return np.zeros(len(self.boxes), bool) if self.detection_ignore is None else np.asarray(self.detection_ignore)


@dataclass
class Evaluation:
    ap50: float
    precision: np.ndarray  # along the ranked detections
    recall: np.ndarray
    scores: np.ndarray  # ranked detection scores
    ground_truth: int  # people in the ground truth
    pckh: float | None = None
    pckh_per_keypoint: np.ndarray | None = None
    mask_iou: float | None = None
    matches: list[list[tuple[int, int]]] = field(default_factory=list)  # per image (truth, detection)
    overlapping: int = 0  # people in the ground truth overlapping another (:func:`grouped`)
    recall_overlapping: float | None = None  # the share of them matched by a detection (None: there are none)

    def to_dict(self) -> dict:
        return {"ap50": round(self.ap50, 4),
                "pckh": None if self.pckh is None else round(self.pckh, 4),
                "pckh_per_keypoint": None if self.pckh_per_keypoint is None
                else [round(float(v), 4) for v in self.pckh_per_keypoint],
                "mask_iou": None if self.mask_iou is None else round(self.mask_iou, 4),
                "detections": int(len(self.scores)),
                "matched": int(sum(len(pairs) for pairs in self.matches)),
                "ground_truth": self.ground_truth, "overlapping": self.overlapping,
                "recall_overlapping": None if self.recall_overlapping is None else round(self.recall_overlapping, 4)}


def average_precision(precision: np.ndarray, recall: np.ndarray) -> float:
    """All-point interpolated AP: area under the monotone envelope of the precision-recall curve."""
    recall = np.concatenate([[0.0], recall, [1.0]])
    precision = np.concatenate([[0.0], precision, [0.0]])
    precision = np.maximum.accumulate(precision[::-1])[::-1]
    steps = np.nonzero(recall[1:] != recall[:-1])[0]
    return float(np.sum((recall[steps + 1] - recall[steps]) * precision[steps + 1]))


def evaluate(images: list[ImageResult]) -> Evaluation:
    ranked = sorted(((float(score), image, detection) for image, result in enumerate(images)
                     for detection, score in enumerate(result.scores)), key=lambda item: -item[0])
    ious = [box_iou(result.boxes, result.truth_boxes) for result in images]
    ignored = [result.ignored() for result in images]
    ignored_detections = [result.detections_ignored() for result in images]
    taken = [np.zeros(len(result.truth_boxes), bool) for result in images]
    matches: list[list[tuple[int, int]]] = [[] for _ in images]
    hits, kept = [], []
    for score, image, detection in ranked:
        overlaps = ious[image][detection] if ious[image].size else np.zeros(0)
        open_truth = np.where(taken[image] | ignored[image], -1.0, overlaps)
        if open_truth.size and open_truth.max() >= IOU_THRESHOLD:
            truth = int(np.argmax(open_truth))
            taken[image][truth] = True
            matches[image].append((truth, detection))
            hits.append(1.0)
        elif overlaps.size and np.any(ignored[image] & (overlaps >= IOU_THRESHOLD)):
            continue  # found only someone we do not ask for: no credit, no penalty
        elif ignored_detections[image][detection]:
            continue  # matched nobody where nobody is annotated: no penalty
        else:
            hits.append(0.0)
        kept.append(score)
    total = int(sum(np.sum(~flags) for flags in ignored))
    true_positives = np.cumsum(hits)
    precision = true_positives / np.arange(1, len(hits) + 1) if hits else np.zeros(0)
    recall = true_positives / total if total else np.zeros(len(hits))
    ap = average_precision(precision, recall) if total else 0.0
    evaluation = Evaluation(ap, precision, recall, np.array(kept), total, matches=matches)
    evaluation.pckh, evaluation.pckh_per_keypoint = _pckh(images, matches)
    evaluation.mask_iou = _mask_iou(images, matches)
    evaluation.overlapping, evaluation.recall_overlapping = _recall_overlapping(images, matches)
    return evaluation


def grouped(boxes: np.ndarray) -> np.ndarray:
    """Which boxes (N, 4) overlap another by IoU >= :data:`GROUP_IOU`."""
    iou = box_iou(boxes, boxes)
    np.fill_diagonal(iou, 0.0)
    return iou.max(axis=1, initial=0.0) >= GROUP_IOU


def _recall_overlapping(images: list[ImageResult], matches: list[list[tuple[int, int]]]) -> tuple[int, float | None]:
    """How many asked-for people overlap another (a hidden, ignored neighbour counts as one), and the share of
    them matched."""
    people = found = 0
    for result, pairs in zip(images, matches, strict=True):
        in_group = grouped(np.asarray(result.truth_boxes, float).reshape(-1, 4)) & ~result.ignored()
        people += int(in_group.sum())
        found += sum(bool(in_group[truth]) for truth, _ in pairs)
    return people, found / people if people else None


def _pckh(images: list[ImageResult], matches: list[list[tuple[int, int]]]) -> tuple[float | None, np.ndarray | None]:
    correct, labelled = None, None
    for result, pairs in zip(images, matches, strict=True):
        if result.truth_keypoints is None or result.keypoints is None:
            continue
        for truth, detection in pairs:
            truth_keypoints = result.truth_keypoints[truth]
            height = result.truth_boxes[truth][3] - result.truth_boxes[truth][1]
            threshold = PCKH_FRACTION * HEAD_FRACTION_OF_HEIGHT * height
            distance = np.linalg.norm(result.keypoints[detection][:, :2] - truth_keypoints[:, :2], axis=1)
            present = truth_keypoints[:, 2] > 0
            correct = (0 if correct is None else correct) + (present & (distance <= threshold))
            labelled = (0 if labelled is None else labelled) + present
    if labelled is None or np.sum(labelled) == 0:
        return None, None
    per_keypoint = np.where(labelled > 0, correct / np.maximum(labelled, 1), np.nan)
    return float(np.sum(correct) / np.sum(labelled)), per_keypoint


def _mask_iou(images: list[ImageResult], matches: list[list[tuple[int, int]]]) -> float | None:
    values = []
    for result, pairs in zip(images, matches, strict=True):
        if result.truth_masks is None or result.masks is None:
            continue
        for truth, detection in pairs:
            a, b = result.truth_masks[truth], result.masks[detection]
            union = np.logical_or(a, b).sum()
            values.append(np.logical_and(a, b).sum() / union if union else 1.0)
    return float(np.mean(values)) if values else None
