"""Each person's keypoints read again from their own crop by the bundle's keypoint model (numpy and onnxruntime only).

The region networks find people and place their keypoints in one pass over the whole region, at the size their
people are planned at. A network that sees one person at a time, cut from the frame, reads TUD-Stadtmitte's people
closer to the reference pose model (each frame and tracked, every seed and both halves) but PETS09's small people
seen from above further from it; read only where it is sure (:data:`PEAK_FLOOR`), it holds PETS09 level. It is read
for people :data:`MIN_READ_HEIGHT_PX` and taller (:func:`worth_reading`), the only ones it changes, and a compile
trains it where most of the scene's people are that tall (``train.crop_pose: auto``;
docs/decisions/0039-keypoints-from-the-crop.md, docs/decisions/0040-keypoint-model-by-size.md).

0. Only people at least :data:`MIN_READ_HEIGHT_PX` tall are read; the others keep the region network's keypoints.
1. Each person's crop is the rectangle the facing model cuts (:func:`vc.deploy.facing.crop_rois`: the box
   :data:`~vc.deploy.facing.CROP_MARGIN` taller, twice as tall as wide), sampled at :data:`CROP_SIZE` by the model's
   own graph (ONNX RoiAlign, as the facing model does), each person from their own part of the frame
   (:func:`vc.deploy.facing.own_parts`).
2. Its output is one heat map per keypoint at :data:`MAP_STRIDE`, each left/right pair in image order (which member is
   the left one is the facing's question, not this model's).
   The crop is read twice, as it is and mirrored (:func:`vc.deploy.facing.mirrored`); the mirror's maps, mirrored
   back and each pair's two maps exchanged (a mirror exchanges their image order), are averaged with the crop's: the
   two readings err apart where the model is unsure (docs/decisions/0043-the-keypoint-model-at-int8-reads-twice.md).
3. Each map's maximum is the keypoint, moved a quarter cell toward the larger of its neighbours on each axis, and
   mapped back to frame pixels (:func:`keypoints_of_maps`).
4. The person's pairs take the order their facing already gave them (``pair_handedness``: > 0, the image-left member
   is the left one), and the places of the keypoints the model is sure of (:data:`PEAK_FLOOR`) replace the region
   network's; the confidences stay the region network's (:func:`with_crop_keypoints`).
"""

from __future__ import annotations

import numpy as np

from vc.deploy.engines import onnxruntime_inference
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois, mirrored, own_parts
from vc.deploy.heatmaps import PAIRS, swap_pairs

#: The crop the keypoint model reads, width x height (pixels): twice the facing model's, as tall as a near person of
#: TUD-Stadtmitte in its region's renders, so that the crop keeps the detail the frame has.
CROP_SIZE = (48, 96)
#: The heat maps' cell, in crop pixels.
MAP_STRIDE = 2
#: The model's output.
MAPS_OUTPUT = "keypoint_maps"
#: A keypoint the model reads replaces the network's only where its heat map's peak is at least this (the targets
#: peak at 1): on PETS09's small people seen from above the model is unsure (peaks below it nearly everywhere) and
#: reads them worse than the networks; on TUD-Stadtmitte's it is sure of most and reads them better. Chosen on both
#: cameras' choosing halves over 0.2-0.5 (docs/decisions/0039-keypoints-from-the-crop.md).
PEAK_FLOOR = 0.3
#: People shorter than this in the frame (their box, pixels) keep the region networks' keypoints, and the model is
#: not run for them: on PETS09's choosing half, reading its 95 % of people under it moved agreement with the
#: reference by 0.000, at a crop each; TUD-Stadtmitte has nobody under it. The highest gate that keeps every gain on
#: both cameras' choosing halves (docs/decisions/0040-keypoint-model-by-size.md).
MIN_READ_HEIGHT_PX = 100.0
_MIRRORED_CHANNELS = swap_pairs(np.arange(17)[:, None], np.ones(len(PAIRS), bool))[:, 0]


def keypoints_of_maps(maps: np.ndarray, rois: np.ndarray) -> np.ndarray:
    """Step 3: heat maps (N, 17, h, w) of the crops cut at ``rois`` (N, 4: x0, y0, x1, y1 in pixel edges) ->
    keypoints (N, 17, 3) in frame pixels (pixel centres at integers), pairs in image order, with each map's peak."""
    count, channels, height, width = maps.shape
    ys, xs = np.divmod(maps.reshape(count, channels, -1).argmax(-1), width)
    person, channel = np.meshgrid(np.arange(count), np.arange(channels), indexing="ij")
    peak = maps[person, channel, ys, xs]
    step_x = np.sign(maps[person, channel, ys, np.minimum(xs + 1, width - 1)]
                     - maps[person, channel, ys, np.maximum(xs - 1, 0)]) * 0.25
    step_y = np.sign(maps[person, channel, np.minimum(ys + 1, height - 1), xs]
                     - maps[person, channel, np.maximum(ys - 1, 0), xs]) * 0.25
    crop_x = (xs + step_x + 0.5) * MAP_STRIDE  # crop pixel edges
    crop_y = (ys + step_y + 0.5) * MAP_STRIDE
    rois = np.asarray(rois, np.float64)
    bin_x = (rois[:, 2] - rois[:, 0]) / CROP_SIZE[0]
    bin_y = (rois[:, 3] - rois[:, 1]) / CROP_SIZE[1]
    return np.stack([rois[:, 0, None] + crop_x * bin_x[:, None] - 0.5,
                     rois[:, 1, None] + crop_y * bin_y[:, None] - 0.5, peak], axis=-1)


def mirrored_back(maps: np.ndarray) -> np.ndarray:
    """Heat maps (N, 17, h, w) read from mirrored crops, as the crops themselves would show them: mirrored back, and
    each pair's two maps exchanged (the mirror's image-left member is the crop's image-right one)."""
    return maps[:, _MIRRORED_CHANNELS, :, ::-1]


def worth_reading(boxes: np.ndarray) -> np.ndarray:
    """Which of the people in ``boxes`` (N, 4: x0, y0, x1, y1) the model reads: those at least
    :data:`MIN_READ_HEIGHT_PX` tall (N,) bool."""
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    return boxes[:, 3] - boxes[:, 1] >= MIN_READ_HEIGHT_PX


def with_crop_keypoints(keypoints: np.ndarray, image_ordered: np.ndarray,
                        pair_handedness: np.ndarray | None) -> np.ndarray:
    """A person's keypoints (17, 3) with the places of the crop's ``image_ordered`` (17, 3: x, y, peak) where the peak
    is at least :data:`PEAK_FLOOR`, their pairs in the order ``pair_handedness`` (8,) gives (> 0 or 0: the
    image-left member is the left one; None: the members' x order of ``keypoints`` stands in); the confidences stay
    (step 4)."""
    if pair_handedness is None:
        left_is_image_left = np.array([keypoints[left, 0] <= keypoints[right, 0] for left, right in PAIRS])
    else:
        left_is_image_left = np.asarray(pair_handedness) >= 0
    read = swap_pairs(image_ordered, ~left_is_image_left)
    replaced = keypoints.copy()
    sure = read[:, 2] >= PEAK_FLOOR
    replaced[sure, :2] = read[sure, :2]
    return replaced


class CropPoseReader:
    """A bundle's keypoint model in onnxruntime: each person's keypoints read from their crop (steps 1-3). One session
    per region runner: the regions run in threads of their own."""

    def __init__(self, model: bytes, threads: int = 1) -> None:
        self.session = onnxruntime_inference(model, threads)

    def read(self, frame: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        """The keypoints (N, 17, 3), pairs in image order, frame pixels, of the people in ``boxes`` (N, 4) of an
        (H, W, 3) uint8 ``frame``."""
        if not len(boxes):
            return np.zeros((0, 17, 3), np.float64)
        rois = crop_rois(boxes)
        maps = [(self._maps(*part) + mirrored_back(self._maps(*mirrored(*part)))) / 2.0
                for part in own_parts(frame, rois)]
        return keypoints_of_maps(np.concatenate(maps), rois)

    def _maps(self, part: np.ndarray, rois: np.ndarray) -> np.ndarray:
        return np.asarray(self.session.run([MAPS_OUTPUT], {FRAME_INPUT: part, ROIS_INPUT: rois})[0], np.float32)
