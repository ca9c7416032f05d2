"""Frames made of people's crops, for the models that read each person from their crop (tests/test_facing.py,
tests/test_crop_pose.py)."""

from __future__ import annotations

import numpy as np

from vc.deploy.facing import CROP_MARGIN


def pasted(crops: np.ndarray, frame_size: tuple[int, int], margin: int,
           spacing: int) -> tuple[np.ndarray, np.ndarray]:
    """A frame of ``frame_size`` (height, width) with each crop (N, h, w, 3) pasted at its own size, ``margin`` px
    from the frame's top and left and ``spacing`` px apart, and the boxes (N, 4) whose crops
    (:func:`vc.deploy.facing.crop_rois`) are exactly those pixels."""
    frame = np.zeros((*frame_size, 3), np.uint8)
    crop_height, crop_width = crops.shape[1:3]
    boxes = []
    for index, crop in enumerate(crops):
        x = margin + index * spacing
        frame[margin:margin + crop_height, x:x + crop_width] = crop
        height = crop_height / CROP_MARGIN
        top = margin + (crop_height - height) / 2 - 0.5
        boxes.append([x - 0.5, top, x + crop_width - 0.5, top + height])
    return frame, np.array(boxes)
