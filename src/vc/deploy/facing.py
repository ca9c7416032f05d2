"""Which way a person faces, read from their crop by the bundle's facing model (numpy and onnxruntime only).

A left/right pair's order is a property of the whole figure: seen from the front, a person's left shoulder and hip
are on the image's right; seen from behind, on its left. The region networks' handedness maps cannot tell at
surveillance sizes (0007: 51-56 % right on their own renders at PETS09's 48 px). A small classifier trained on the
compile's renders for that one question can: it looks at the whole person, face or hair, toes, the figure's
front (docs/decisions/0027-facing-from-the-crop.md).

1. Each person's crop is the box, :data:`CROP_MARGIN` taller, twice as tall as wide about the box's centre
   (:func:`crop_rois`). The model cuts the crops itself: its graph takes the frame (1, H, W, 3) uint8 and the crops'
   rectangles (N, 4), and samples each at :data:`CROP_SIZE` by ONNX's RoiAlign, every bin the average of 2 x 2
   samples spread over it (onnxruntime's C++, one call a frame; numpy resampling per person cost 0.6 ms each).
2. Its output is one logit per person: > 0 seen from the front.
3. The person's pairs are ordered by that facing, and their handedness becomes ``-tanh(logit / 2)`` on every pair
   (> 0 seen from behind, its size the model's confidence), which the tracker weighs against the walk
   (:mod:`vc.deploy.tracking`).
"""

from __future__ import annotations

import numpy as np

from vc.deploy.engines import onnxruntime_inference
from vc.deploy.heatmaps import swap_pairs

#: The crop the facing model reads, width x height (pixels).
CROP_SIZE = (32, 64)
#: The crop's height over the box's: a little ground and air around the person.
CROP_MARGIN = 1.1
#: The model's inputs and output.
FRAME_INPUT, ROIS_INPUT, OUTPUT_NAME = "frame", "rois", "front_logit"


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


class FacingReader:
    """A bundle's facing model in onnxruntime: the front logit of each person (steps 1-2). One session per region
    runner: the regions run in threads of their own."""

    def __init__(self, model: bytes, threads: int = 1) -> None:
        self.session = onnxruntime_inference(model, threads)

    def front_logits(self, frame: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        """(N,) logits, > 0 seen from the front, of the people in ``boxes`` (N, 4) of an (H, W, 3) uint8 ``frame``."""
        if not len(boxes):
            return np.zeros(0, np.float32)
        rois = crop_rois(boxes)
        # only the part of the frame the crops reach goes into the graph (its cast and transpose cost per pixel)
        height, width = frame.shape[:2]
        x0, y0 = (int(np.clip(np.floor(rois[:, index].min()) - 1, 0, limit)) for index, limit in ((0, width - 1),
                                                                                                   (1, height - 1)))
        x1, y1 = (int(np.clip(np.ceil(rois[:, index].max()) + 1, low + 1, limit)) for index, low, limit in
                  ((2, x0, width), (3, y0, height)))
        part = np.ascontiguousarray(frame[None, y0:y1, x0:x1])
        shifted = rois - np.array([x0, y0, x0, y0], np.float32)
        return np.asarray(self.session.run(None, {FRAME_INPUT: part, ROIS_INPUT: shifted})[0]).reshape(-1)


def ordered_by_facing(keypoints: np.ndarray, pair_handedness: np.ndarray, front_logit: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """A person's keypoints (17, k), their pairs ordered by the network's ``pair_handedness`` (> 0: the image-left
    member is the left one), reordered by the facing model's ``front_logit``, and the handedness that now orders
    them (step 3)."""
    behind = -float(np.tanh(front_logit / 2.0))
    reordered = swap_pairs(keypoints, (np.asarray(pair_handedness) >= 0) != (behind > 0))
    return reordered, np.full(len(pair_handedness), behind, np.float32)
