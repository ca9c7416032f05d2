"""Pose on real people without keypoint ground truth: agreement with a reference pose model — a proxy, stated as one.

Real surveillance frames come with boxes, not keypoints. What can be measured is how often the bundle puts a
keypoint where a pose model trained on real photos (a YOLO-pose ONNX model through ``vc-eval --external``) puts
it:

1. Each detector keeps its detections at its own operating point (the score threshold of best F1,
   :func:`vc.evaluation.misses.operating_point`) and is matched to the ground-truth boxes at IoU >= 0.5
   (:func:`vc.evaluation.metrics.evaluate`'s greedy matching).
2. On every ground-truth person both detectors found, each keypoint the reference is confident of (confidence >=
   :data:`REFERENCE_CONFIDENCE`) is compared with the other detector's: it agrees when within
   :data:`AGREEMENT_HEAD_SIZES` head sizes, a head size being 1/8 of the ground-truth box height (PCKh's head
   size in :mod:`vc.evaluation.metrics`).
3. The share that agrees, per COCO keypoint and overall, is the agreement.
4. Which of a pair is the left one is a property of the whole figure (which way the person faces), and one
   wrong call moves all eight pairs. So each person is also compared with their pairs exchanged: the people
   for whom more keypoints agree exchanged, and the agreement were each person's left and right the reference's
   (``overall_if_left_right_matched``), say how much of the disagreement is left against right alone.
5. Where each keypoint sits against the reference's, in that better order: the median of (ours - theirs) / head
   size, x and y (``median_offset_head_sizes``). Random errors scatter around zero; a convention or a bias
   shows as a shift — a face read higher than the reference reads it, ankles lower.

The reference has errors of its own, and COCO's annotators (whose convention a COCO-trained model learns) mark
hips and shoulders away from the anatomical joint centres a rendered skeleton has: agreement is not accuracy. A
second reference (the same family at another input size) measured against the first shows the ceiling the proxy
allows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult
from vc.evaluation.misses import operating_point
from vc.keypoints import COCO_KEYPOINTS

#: The reference's keypoints at or above this confidence are compared.
REFERENCE_CONFIDENCE = 0.5
#: A keypoint agrees within this many head sizes of the reference's.
AGREEMENT_HEAD_SIZES = 0.5


@dataclass(frozen=True)
class PoseAgreement:
    """Keypoints compared and agreeing, per COCO keypoint, over the people both detectors found."""

    compared: np.ndarray  # (17,) int
    agreeing: np.ndarray  # (17,) int
    people: int
    left_right_swapped: int = 0  # people for whom more keypoints agree with their pairs exchanged
    agreeing_if_left_right_matched: np.ndarray | None = None  # (17,) int: each person in the better order
    median_offset: np.ndarray | None = None  # (17, 2) head sizes, ours - theirs, in the better order; NaN: none

    @property
    def overall(self) -> float | None:
        total = int(self.compared.sum())
        return float(self.agreeing.sum() / total) if total else None

    def per_keypoint(self) -> dict[str, float | None]:
        return {name: float(agree / compared) if compared else None
                for name, agree, compared in zip(COCO_KEYPOINTS, self.agreeing, self.compared, strict=True)}

    @property
    def overall_if_left_right_matched(self) -> float | None:
        total = int(self.compared.sum())
        if not total or self.agreeing_if_left_right_matched is None:
            return None
        return float(self.agreeing_if_left_right_matched.sum() / total)

    def to_dict(self) -> dict:
        overall, matched = self.overall, self.overall_if_left_right_matched
        return {"overall": None if overall is None else round(overall, 4), "people": self.people,
                "keypoints_compared": int(self.compared.sum()),
                "per_keypoint": {name: None if value is None else round(value, 4)
                                 for name, value in self.per_keypoint().items()},
                "people_left_right_swapped": self.left_right_swapped,
                "overall_if_left_right_matched": None if matched is None else round(matched, 4),
                **({} if self.median_offset is None else {"median_offset_head_sizes": {
                    name: None if np.isnan(offset).any() else [round(float(c), 3) for c in offset]
                    for name, offset in zip(COCO_KEYPOINTS, self.median_offset, strict=True)}})}


def matched_people(images: Sequence[ImageResult]) -> list[dict[int, int]]:
    """Per image, ground-truth index -> detection index of the people found at the operating point."""
    point = operating_point(images)
    if point is None:
        return [{} for _ in images]
    return [{truth: int(kept[detection]) for truth, detection in matches.items()}
            for kept, matches in zip(point.kept, point.matches, strict=True)]


def pose_agreement(candidate: Sequence[ImageResult], reference: Sequence[ImageResult]) -> PoseAgreement:
    """How often ``candidate``'s keypoints agree with ``reference``'s (both per frame, over the same ground truth,
    with ``keypoints`` (M, 17, 2+) of x, y[, confidence]; see the module docstring)."""
    if len(candidate) != len(reference):
        raise ValueError(f"{len(candidate)} frames against {len(reference)}: both must cover the same frames")
    compared = np.zeros(len(COCO_KEYPOINTS), int)
    agreeing = np.zeros(len(COCO_KEYPOINTS), int)
    agreeing_matched = np.zeros(len(COCO_KEYPOINTS), int)
    offsets: list[list[np.ndarray]] = [[] for _ in COCO_KEYPOINTS]
    people = swapped = 0
    for ours, theirs, our_matches, their_matches in zip(candidate, reference, matched_people(candidate),
                                                        matched_people(reference), strict=True):
        for truth in sorted(set(our_matches) & set(their_matches)):
            box = ours.truth_boxes[truth]
            head = HEAD_FRACTION_OF_HEIGHT * (box[3] - box[1])
            our_keypoints = np.asarray(ours.keypoints[our_matches[truth]], np.float64)
            their_keypoints = np.asarray(theirs.keypoints[their_matches[truth]], np.float64)
            confident = their_keypoints[:, 2] >= REFERENCE_CONFIDENCE
            exchanged = swap_pairs(our_keypoints, [True] * len(PAIRS))
            agree, agree_exchanged = (
                confident & (np.linalg.norm(keypoints[:, :2] - their_keypoints[:, :2], axis=1)
                             <= AGREEMENT_HEAD_SIZES * head)
                for keypoints in (our_keypoints, exchanged))
            compared += confident
            agreeing += agree
            exchanged_better = agree_exchanged.sum() > agree.sum()
            agreeing_matched += agree_exchanged if exchanged_better else agree
            better = exchanged if exchanged_better else our_keypoints
            for keypoint in np.flatnonzero(confident):
                offsets[keypoint].append((better[keypoint, :2] - their_keypoints[keypoint, :2]) / head)
            swapped += int(exchanged_better)
            people += 1
    median_offset = np.array([np.median(found, axis=0) if found else [np.nan, np.nan] for found in offsets])
    return PoseAgreement(compared, agreeing, people, swapped, agreeing_matched, median_offset)
