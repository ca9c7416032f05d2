"""Heat-map layout and the geometry between network input pixels and heat-map cells (numpy only).

One place for both directions so that target encoding (``vc.model.codec``) and decoding (``vc.deploy.decode``)
can never disagree. Channels: person centre, the 17 COCO keypoints in COCO order, the segmentation mask.

Pixel convention (DESIGN.md): the centre of the top-left pixel is (0, 0). A heat map at output stride ``s``
has cell ``j`` covering input pixels ``j*s .. j*s + s - 1``, so its centre lies at input ``j*s + (s - 1)/2``.
"""

from __future__ import annotations

import numpy as np

from vc.keypoints import COCO_KEYPOINTS

CENTRE_CHANNEL = 0
KEYPOINT_CHANNELS = slice(1, 1 + len(COCO_KEYPOINTS))
MASK_CHANNEL = 1 + len(COCO_KEYPOINTS)
HEATMAP_CHANNELS = MASK_CHANNEL + 1


def input_to_cells(xy: np.ndarray, stride: int) -> np.ndarray:
    """Input pixel coordinates -> heat-map cell coordinates (same convention: cell centres at integers)."""
    return (np.asarray(xy, np.float64) + 0.5) / stride - 0.5


def cells_to_input(xy: np.ndarray, stride: int) -> np.ndarray:
    """Heat-map cell coordinates -> input pixel coordinates (inverse of :func:`input_to_cells`)."""
    return (np.asarray(xy, np.float64) + 0.5) * stride - 0.5
