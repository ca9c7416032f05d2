"""Heat-map layout and the geometry between network input pixels and heat-map cells (numpy only).

One place for both directions so that target encoding (``vc.model.codec``) and decoding (``vc.deploy.decode``)
can never disagree. Channels (:data:`CHANNEL_NAMES`): the person centre; the 17 COCO keypoints in COCO order,
except that each left/right pair (:data:`PAIRS`) is in image order, its first map holding whichever member lies
further left in the image; the segmentation mask; one handedness map per pair, +1 over a person's pixels where
the pair's image-left member is the person's left one, -1 where it is the right one; in networks trained with
them, the two centre-offset maps (:data:`CENTRE_OFFSET_CHANNELS`), the fine centre map
(:data:`FINE_CENTRE_CHANNELS`) and the head and size maps (:data:`HEAD_CHANNEL`, :data:`SIZE_CHANNEL`).

Why image order: a wrist looks like a wrist, so which wrist it is cannot be seen where it is. Asked for anatomical
maps, the network hedges and puts both limbs in both maps (on the demo scene 99 % of the pairs that lie apart
were decoded as one point, and PCKh stayed at 0.70). Which member is further left is visible locally; whether it
is the left one depends on which way the person faces and how they stride, a property of the whole figure that
the handedness maps carry over the person's pixels and the decoder reads at the centre.

The first networks emitted :data:`ANATOMICAL_CHANNELS` maps, the pairs in anatomical order and no handedness: a
layout this version neither trains nor decodes, whose bundles and checkpoints are refused
(docs/decisions/0003-decoder-settings.md). The layouts it has (:data:`LAYOUTS`) differ by the maps they add at the
end, and the decoder tells them apart by their channel count.

Pixel convention (docs/design.md): the centre of the top-left pixel is (0, 0). A heat map at output stride ``s``
has cell ``j`` covering input pixels ``j*s .. j*s + s - 1``, so its centre lies at input ``j*s + (s - 1)/2``.
"""

from __future__ import annotations

import numpy as np

from vc.keypoints import COCO_KEYPOINTS

CENTRE_CHANNEL = 0
KEYPOINT_CHANNELS = slice(1, 1 + len(COCO_KEYPOINTS))
MASK_CHANNEL = 1 + len(COCO_KEYPOINTS)
#: (left, right) keypoint indices of the eyes, ears, shoulders, elbows, wrists, hips, knees and ankles.
PAIRS: tuple[tuple[int, int], ...] = tuple(
    (index, COCO_KEYPOINTS.index(name.replace("left_", "right_")))
    for index, name in enumerate(COCO_KEYPOINTS) if name.startswith("left_"))
_LEFT_MEMBERS, _RIGHT_MEMBERS = (np.array(members) for members in zip(*PAIRS, strict=True))
HANDEDNESS_CHANNELS = slice(MASK_CHANNEL + 1, MASK_CHANNEL + 1 + len(PAIRS))
HEATMAP_CHANNELS = HANDEDNESS_CHANNELS.stop
#: The retired layout's channel count (centre, 17 keypoints in anatomical order, mask): what a refusal names.
ANATOMICAL_CHANNELS = MASK_CHANNEL + 1
#: Two maps after the handedness ones, in networks trained to emit them: over each person's pixels, the (x, y) from
#: the cell to that person's own centre, in the person's heights. Every pixel votes for the person it belongs to,
#: so two people in one blob of the centre map are two clusters of votes (the centre offsets of Panoptic-DeepLab,
#: Cheng et al., CVPR 2020), and a person's mask is the pixels that vote for them.
CENTRE_OFFSET_CHANNELS = slice(HEATMAP_CHANNELS, HEATMAP_CHANNELS + 2)
OFFSET_CHANNELS = CENTRE_OFFSET_CHANNELS.stop
#: Four maps after the offsets, in networks trained to emit them: the centre map at twice the heat maps' resolution
#: (:data:`FINE_FACTOR`), stored space-to-depth — map ``2 dy + dx`` holds the fine cells (2 r + dy, 2 c + dx) at cell
#: (r, c) (:func:`fine_centre_map`). Two people one behind another stand 1.5-2 cells apart at a 48 px person's
#: stride-4 cells, where one centre peak can only be found for both; on the fine grid they are 3-4 cells apart.
#: Learning it is what separates them; the decoder reads the coarse map's peaks
#: (docs/decisions/0010-fine-centre-map.md). Four channels of the last 1x1 convolution cost next to nothing at run
#: time.
FINE_FACTOR = 2
FINE_CENTRE_CHANNELS = slice(OFFSET_CHANNELS, OFFSET_CHANNELS + FINE_FACTOR**2)
FINE_CHANNELS = FINE_CENTRE_CHANNELS.stop
#: Two maps after the fine centre map, in networks trained to emit them: a Gaussian at each person's head (the
#: middle of their nose, eyes and ears), and over each person's pixels the log of their height in
#: :data:`SIZE_UNIT_CELLS` cells. People in a group whose centres blur into one peak keep their heads apart; at a
#: head, the centre offset times the size map's height is the way to the person's centre, so the decoder reads a
#: second set of people from the heads (docs/decisions/0058-a-head-map-in-every-region.md).
HEAD_CHANNEL = FINE_CHANNELS
SIZE_CHANNEL = FINE_CHANNELS + 1
HEAD_CHANNELS = SIZE_CHANNEL + 1
#: The size map's unit, in heat-map cells: it holds log(height / SIZE_UNIT_CELLS), about 0 for PETS09's middle
#: distance (80 px at stride 4) and within +-2 for people from 15 to 600 px.
SIZE_UNIT_CELLS = 20.0
#: Every layout a network emits, by its channel count: image-ordered pairs with handedness, those with the centre
#: offsets, those with a fine centre map too, and those with the head and size maps too.
LAYOUTS = (HEATMAP_CHANNELS, OFFSET_CHANNELS, FINE_CHANNELS, HEAD_CHANNELS)


def swap_pairs(keypoints: np.ndarray, swapped) -> np.ndarray:
    """A copy of keypoints (..., 17, k) with the two members of each pair (:data:`PAIRS`) exchanged where
    ``swapped`` (..., one flag per pair) is true: image order <-> anatomical order, in either direction. Several
    people at once: keypoints (N, 17, k) and flags (N, pairs)."""
    swapped = np.asarray(swapped, bool)
    order = np.array(np.broadcast_to(np.arange(len(COCO_KEYPOINTS)), (*swapped.shape[:-1], len(COCO_KEYPOINTS))))
    order[..., _LEFT_MEMBERS] = np.where(swapped, _RIGHT_MEMBERS, _LEFT_MEMBERS)
    order[..., _RIGHT_MEMBERS] = np.where(swapped, _LEFT_MEMBERS, _RIGHT_MEMBERS)
    return np.take_along_axis(np.asarray(keypoints), order[..., None], axis=-2)  # a copy


def channel_names(channels: int = HEATMAP_CHANNELS) -> tuple[str, ...]:
    """What each map of a network's output holds (written into bundles), for each of the :data:`LAYOUTS`."""
    if channels not in LAYOUTS:
        raise ValueError(f"no heat-map layout has {channels} channels")
    slots = [name.replace("left_", "").replace("right_", "") + ("_image_left" if name.startswith("left_") else
                                                                  "_image_right" if name.startswith("right_") else "")
             for name in COCO_KEYPOINTS]
    handedness = [COCO_KEYPOINTS[left].removeprefix("left_") + "_handedness" for left, _ in PAIRS]
    offsets = ("centre_offset_x", "centre_offset_y") if channels >= OFFSET_CHANNELS else ()
    fine = tuple(f"fine_centre_{dy}{dx}" for dy in range(FINE_FACTOR) for dx in range(FINE_FACTOR)
                 ) if channels >= FINE_CHANNELS else ()
    head = ("head", f"log_height_{SIZE_UNIT_CELLS:g}_cells") if channels == HEAD_CHANNELS else ()
    return ("centre", *slots, "mask", *handedness, *offsets, *fine, *head)


def fine_centre_map(maps: np.ndarray) -> np.ndarray:
    """The fine centre map (..., FINE_FACTOR h, FINE_FACTOR w) from its space-to-depth channels (..., 4, h, w)
    (:data:`FINE_CENTRE_CHANNELS` of a network's output)."""
    *batch, _, height, width = maps.shape
    blocks = maps.reshape(*batch, FINE_FACTOR, FINE_FACTOR, height, width)  # (..., dy, dx, r, c)
    order = (*range(len(batch)), len(batch) + 2, len(batch), len(batch) + 3, len(batch) + 1)  # (..., r, dy, c, dx)
    return blocks.transpose(order).reshape(*batch, FINE_FACTOR * height, FINE_FACTOR * width)


def fine_centre_channels(fine: np.ndarray) -> np.ndarray:
    """The inverse of :func:`fine_centre_map`: (..., FINE_FACTOR h, FINE_FACTOR w) -> (..., 4, h, w)."""
    *batch, fine_height, fine_width = fine.shape
    height, width = fine_height // FINE_FACTOR, fine_width // FINE_FACTOR
    blocks = fine.reshape(*batch, height, FINE_FACTOR, width, FINE_FACTOR)  # (..., r, dy, c, dx)
    order = (*range(len(batch)), len(batch) + 1, len(batch) + 3, len(batch), len(batch) + 2)  # (..., dy, dx, r, c)
    return blocks.transpose(order).reshape(*batch, FINE_FACTOR**2, height, width)


def cells_to_fine(xy: np.ndarray) -> np.ndarray:
    """Heat-map cell coordinates -> fine centre-map coordinates (both with cell centres at integers: a cell of
    stride s is FINE_FACTOR fine cells of stride s / 2 as a fine cell is s / 2 pixels)."""
    return cells_to_input(xy, FINE_FACTOR)


def input_to_cells(xy: np.ndarray, stride: int) -> np.ndarray:
    """Input pixel coordinates -> heat-map cell coordinates (same convention: cell centres at integers)."""
    return (np.asarray(xy, np.float64) + 0.5) / stride - 0.5


def cells_to_input(xy: np.ndarray, stride: int) -> np.ndarray:
    """Heat-map cell coordinates -> input pixel coordinates (inverse of :func:`input_to_cells`)."""
    return (np.asarray(xy, np.float64) + 0.5) * stride - 0.5
