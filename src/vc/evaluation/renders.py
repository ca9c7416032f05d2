"""Measuring on renders: which rendered people a detector is asked for, and one render's truth and detections in
the metrics' terms (:mod:`vc.evaluation.metrics`). Torch-free: training's held-out evaluation and the bundle
self-test share it.

Ground truth is each person's full (amodal) box, clipped to the input: the decoder's box is the person's expected
height at that position, not the visible part. People mostly hidden or cut off are ``ignore``: a detector is not
asked to find someone of whom less than :data:`MIN_VISIBLE_HEIGHT` of the height shows, or whose centre is off
the input, nor penalised for finding them.
"""

from __future__ import annotations

import numpy as np

from vc.deploy.decode import DecodedPerson
from vc.evaluation.metrics import ImageResult

#: Fraction of a person's full height that must be visible for the evaluation to ask for them.
MIN_VISIBLE_HEIGHT = 0.5


def _xyxy(box_xywh: list[float]) -> np.ndarray:
    x, y, width, height = box_xywh
    return np.array([x, y, x + width, y + height])


def asked_for(annotation: dict, input_size: tuple[int, int]) -> bool:
    """Whether the evaluation counts a person (see the module docstring)."""
    width, height = input_size
    centre = annotation.get("center")
    if centre is None or not (-0.5 <= centre[0] <= width - 0.5 and -0.5 <= centre[1] <= height - 0.5):
        return False
    return annotation["bbox"][3] >= MIN_VISIBLE_HEIGHT * annotation["amodal_bbox"][3]


def image_result(annotations: list[dict], instances: np.ndarray, people: list[DecodedPerson],
                 stride: int) -> ImageResult:
    """One sample's truth and decoded people in the metrics' terms (boxes clipped to the input)."""
    height, width = instances.shape
    limits = np.array([-0.5, -0.5, width - 0.5, height - 0.5])
    boxes = np.array([person.box for person in people]).reshape(-1, 4)
    boxes = np.clip(boxes, limits[[0, 1, 0, 1]], limits[[2, 3, 2, 3]])
    return ImageResult(
        truth_boxes=np.array([_xyxy(a["amodal_bbox"]) for a in annotations]).reshape(-1, 4),
        boxes=boxes,
        scores=np.array([person.score for person in people]),
        truth_keypoints=np.array([np.reshape(a["keypoints"], (-1, 3)) for a in annotations]).reshape(-1, 17, 3),
        keypoints=np.array([person.keypoints for person in people]).reshape(-1, 17, 3),
        truth_masks=[instances == a["instance_id"] for a in annotations],
        masks=[np.repeat(np.repeat(person.mask_cells, stride, axis=0), stride, axis=1)[:height, :width]
               for person in people],
        truth_ignore=np.array([not asked_for(a, (width, height)) for a in annotations], bool),
    )
