"""Which way a person faces, read from their crop by the bundle's facing model (numpy and onnxruntime only).

A left/right pair's order is a property of the whole figure: seen from the front, a person's left shoulder and hip
are on the image's right; seen from behind, on its left. The region networks' handedness maps cannot tell at
surveillance sizes (0007: 51-56 % right on their own renders at PETS09's 48 px). A small classifier trained on the
compile's renders for that one question can: it looks at the whole person, face or hair, toes, the figure's
front (docs/decisions/0027-facing-from-the-crop.md). A second one beside it reads where the face points across
the image: where the networks cannot tell, they put the nose between the ears, where no face in profile has it
(docs/decisions/0038-the-face-turned-from-the-crop.md).

1. Each person's crop is the box, :data:`CROP_MARGIN` taller, twice as tall as wide about the box's centre
   (:func:`crop_rois`). The model cuts the crops itself: its graph takes the frame (1, H, W, 3) uint8 and the crops'
   rectangles (N, 4), and samples each at :data:`CROP_SIZE` by ONNX's RoiAlign, every bin the average of 2 x 2
   samples spread over it (onnxruntime's C++; numpy resampling per person cost 0.6 ms each). Each person is cut
   from their own part of the frame, one call each, so that what the model reads of them does not depend on who
   else is in the frame (:func:`own_parts`).
2. Its outputs are one logit per person, > 0 seen from the front, and, from models exported since 0038, where the
   face points across the image (-1 in profile facing the image's left, 0 along the view, 1 facing its right).
   From models exported since 0041, a second front logit read from the head's colours alone: for people shorter
   than :data:`HEAD_READ_BELOW_PX` the front logit is that one plus :data:`CLASSIFIER_WEIGHT_BELOW` times the
   classifier's. At PETS09's sizes seen from above the classifier carries little of what it learns on renders to
   real people, and the head's light face under darker hair carries more (:func:`front_logits`;
   docs/decisions/0041-the-heads-colours-for-small-people.md). People :data:`MIRRORED_FROM_PX` and taller are read
   twice, their crop as it is and mirrored (:func:`mirrored`), and each output is the mean of the two readings, the
   mirror's face turned back: a mirror keeps a front a front, so where the model is unsure of a person its two
   readings err apart (docs/decisions/0042-tall-people-read-twice.md).
3. The person's pairs are ordered by that facing, and their handedness becomes ``-tanh(logit / 2)`` on every pair
   (> 0 seen from behind, its size the model's confidence). A tracker averages it over the track where their walk
   is not clear (:mod:`vc.deploy.tracking`).
4. The nose and the eyes are put ahead of the ears' midpoint by the body model's distances times where the face
   points (:func:`face_ahead`); the tracker turns them the same way by the walk where it decides the facing.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import NamedTuple

import numpy as np

from vc.deploy.engines import onnxruntime_inference
from vc.deploy.heatmaps import swap_pairs
from vc.keypoints import COCO_KEYPOINTS

#: The crop the facing model reads, width x height (pixels).
CROP_SIZE = (32, 64)
#: The crop's height over the box's: a little ground and air around the person.
CROP_MARGIN = 1.1
#: The model's inputs and outputs (the second only in models exported since decision 0038, the third since 0041).
FRAME_INPUT, ROIS_INPUT, OUTPUT_NAME, ACROSS_OUTPUT = "frame", "rois", "front_logit", "face_across"
HEAD_OUTPUT = "head_front_logit"
#: People shorter than this (their box, pixels) are read front or behind mostly by their head's colours: PETS09's,
#: 50-105 px tall, more often the reference's way on both halves; TUD-Stadtmitte's, 140 px and taller, are read
#: better by the classifier alone (docs/decisions/0041-the-heads-colours-for-small-people.md).
HEAD_READ_BELOW_PX = 100.0
#: ... and the classifier's logit weighs in at this share of the head's: where the head says little (a hood, a
#: face no lighter than the hair), the classifier still decides. Chosen on PETS09's choosing half (0041).
CLASSIFIER_WEIGHT_BELOW = 0.05
#: People this tall or taller (their box, pixels) are read twice, their crop and its mirror image, and the two
#: readings averaged: TUD-Stadtmitte's people, 140 px and taller, are read the reference's way more often; PETS09's
#: small ones, read by their heads, are not (docs/decisions/0042-tall-people-read-twice.md).
MIRRORED_FROM_PX = 100.0
#: How far the nose and the eyes stand ahead of the ears' midpoint, in fractions of the person's height: the
#: renderer's body model (anny's template, ``render/bodies.py``) has its nose 0.103 m and its eyes 0.081 m ahead of
#: the ears on a 1.67 m body (tests/test_bodies.py checks these against it).
FACE_AHEAD_OF_EARS = {"nose": 0.062, "eyes": 0.048}
_NOSE = COCO_KEYPOINTS.index("nose")
_EYES = [COCO_KEYPOINTS.index("left_eye"), COCO_KEYPOINTS.index("right_eye")]
_EARS = [COCO_KEYPOINTS.index("left_ear"), COCO_KEYPOINTS.index("right_ear")]


def crop_rois(boxes: np.ndarray) -> np.ndarray:
    """The crops' rectangles (N, 4) float32, x0, y0, x1, y1 in pixel edges (a pixel's centre at +0.5), of people's
    ``boxes`` (N, 4: outer edges, pixel centres at integers): :data:`CROP_MARGIN` times the box's height, twice as
    tall as wide, about the box's centre (step 1)."""
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    height = (boxes[:, 3] - boxes[:, 1]) * CROP_MARGIN
    width = height * CROP_SIZE[0] / CROP_SIZE[1]
    centre_x, centre_y = (boxes[:, 0] + boxes[:, 2]) / 2.0 + 0.5, (boxes[:, 1] + boxes[:, 3]) / 2.0 + 0.5
    return np.stack([centre_x - width / 2, centre_y - height / 2, centre_x + width / 2, centre_y + height / 2],
                    axis=1).astype(np.float32)


def mirrored(part: np.ndarray, rois: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A model's frame input (1, h, w, 3) mirrored left to right, and the rectangles (N, 4) that cut from it the
    mirror images of the crops ``rois`` (N, 4, pixel edges) cut from ``part``: RoiAlign's samples are symmetric
    about each bin's centre, so the crops are the first's mirrored, to float rounding."""
    width = part.shape[2]
    rois = np.asarray(rois, np.float32).reshape(-1, 4)
    return (np.ascontiguousarray(part[:, :, ::-1]),
            np.stack([width - rois[:, 2], rois[:, 1], width - rois[:, 0], rois[:, 3]], axis=1).astype(np.float32))


def frame_part(frame: np.ndarray, rois: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The part of an (H, W, 3) ``frame`` that crops at ``rois`` (N, 4) reach, as a model's frame input (1, h, w, 3),
    and the rectangles within it: only that part goes into a crop graph, whose cast and transpose cost per pixel."""
    height, width = frame.shape[:2]
    x0, y0 = (int(np.clip(np.floor(rois[:, index].min()) - 1, 0, limit)) for index, limit in ((0, width - 1),
                                                                                               (1, height - 1)))
    x1, y1 = (int(np.clip(np.ceil(rois[:, index].max()) + 1, low + 1, limit)) for index, low, limit in
              ((2, x0, width), (3, y0, height)))
    return np.ascontiguousarray(frame[None, y0:y1, x0:x1]), rois - np.array([x0, y0, x0, y0], np.float32)


def own_parts(frame: np.ndarray, rois: np.ndarray, mirror: bool = False) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Each person's own :func:`frame_part` of ``frame`` and their crop's rectangle (1, 4) within it, each
    :func:`mirrored` with ``mirror``: a crop graph reads each person from their own part, so that what it reads of
    them does not depend on who else is in the frame. Cut from a part shared by everyone, a person's RoiAlign samples
    are computed from another origin, round otherwise in float32, and the int8 keypoint model moved a keypoint by up
    to 30 px for that (docs/decisions/0059-each-person-read-from-their-own-part.md)."""
    for roi in np.asarray(rois, np.float32).reshape(-1, 4):
        part = frame_part(frame, roi[None])
        yield mirrored(*part) if mirror else part


class FacingReading(NamedTuple):
    """What the facing model reads of N people: front logits (N,), and where each face points across the image
    (N,) in [-1, 1], or None from a model exported before it read that."""

    front_logits: np.ndarray
    across: np.ndarray | None


def front_logits(classifier: np.ndarray, head: np.ndarray | None, heights: np.ndarray) -> np.ndarray:
    """Each person's front logit (N,) from the classifier's and, where the model reads it, the head's (step 2):
    people shorter than :data:`HEAD_READ_BELOW_PX` take the head's plus :data:`CLASSIFIER_WEIGHT_BELOW` times the
    classifier's, the others the classifier's."""
    classifier = np.asarray(classifier, np.float32).reshape(-1)
    if head is None:
        return classifier
    small = np.asarray(heights).reshape(-1) < HEAD_READ_BELOW_PX
    return np.where(small, np.asarray(head, np.float32).reshape(-1) + CLASSIFIER_WEIGHT_BELOW * classifier,
                    classifier).astype(np.float32)


class FacingReader:
    """A bundle's facing model in onnxruntime: the front logit of each person and where their face points (steps
    1-2). One session per region runner: the regions run in threads of their own."""

    def __init__(self, model: bytes, threads: int = 1) -> None:
        self.session = onnxruntime_inference(model, threads)
        names = {output.name for output in self.session.get_outputs()}
        self.reads_across, self.reads_head = ACROSS_OUTPUT in names, HEAD_OUTPUT in names
        self.outputs = [OUTPUT_NAME] + [name for name, read in ((ACROSS_OUTPUT, self.reads_across),
                                                                (HEAD_OUTPUT, self.reads_head)) if read]

    def read(self, frame: np.ndarray, boxes: np.ndarray) -> FacingReading:
        """What the model reads of the people in ``boxes`` (N, 4) of an (H, W, 3) uint8 ``frame``."""
        if not len(boxes):
            return FacingReading(np.zeros(0, np.float32), np.zeros(0, np.float32) if self.reads_across else None)
        boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
        heights = boxes[:, 3] - boxes[:, 1]
        rois = crop_rois(boxes)
        found = self._outputs(own_parts(frame, rois))
        tall = heights >= MIRRORED_FROM_PX
        if tall.any():
            seen = self._outputs(own_parts(frame, rois[tall], mirror=True))
            if self.reads_across:
                seen[ACROSS_OUTPUT] = -seen[ACROSS_OUTPUT]  # a mirror turns the face the other way
            for name in self.outputs:
                found[name][tall] = (found[name][tall] + seen[name]) / 2.0
        return FacingReading(front_logits(found[OUTPUT_NAME], found.get(HEAD_OUTPUT), heights),
                             found[ACROSS_OUTPUT] if self.reads_across else None)

    def _outputs(self, parts: Iterator[tuple[np.ndarray, np.ndarray]]) -> dict[str, np.ndarray]:
        """Each of the model's outputs (N,) float32 for the N people's own ``parts`` (:func:`own_parts`)."""
        readings = [self.session.run(self.outputs, {FRAME_INPUT: part, ROIS_INPUT: roi}) for part, roi in parts]
        return {name: np.asarray([reading[index] for reading in readings], np.float32).reshape(-1)
                for index, name in enumerate(self.outputs)}


def ordered_by_facing(keypoints: np.ndarray, pair_handedness: np.ndarray, front_logit: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """A person's keypoints (17, k), their pairs ordered by the network's ``pair_handedness`` (> 0: the image-left
    member is the left one), reordered by the facing model's ``front_logit``, and the handedness that now orders
    them (step 3)."""
    behind = -float(np.tanh(front_logit / 2.0))
    reordered = swap_pairs(keypoints, (np.asarray(pair_handedness) >= 0) != (behind > 0))
    return reordered, np.full(len(pair_handedness), behind, np.float32)


def face_ahead(keypoints: np.ndarray, height: float, across: float) -> np.ndarray:
    """The keypoints (17, 3) with the nose and the eyes (their midpoint; their spacing kept) put ahead of the ears'
    midpoint by :data:`FACE_AHEAD_OF_EARS` of the person's ``height`` (px) times ``across`` (-1: in profile facing
    the image's left, 0: facing along the view, 1: in profile facing right) (step 4)."""
    turned = keypoints.copy()
    ears_x = float(keypoints[_EARS, 0].mean())
    turned[_NOSE, 0] = ears_x + FACE_AHEAD_OF_EARS["nose"] * height * across
    turned[_EYES, 0] += ears_x + FACE_AHEAD_OF_EARS["eyes"] * height * across - float(keypoints[_EYES, 0].mean())
    return turned
