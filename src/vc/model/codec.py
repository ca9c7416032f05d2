"""Target encoding: a rendered sample's labels -> the heat maps ScenePoseNet learns (numpy, kept apart from the
network, as mmpose keeps its codecs).

* Centre: a Gaussian at the person's centre (the point half its stature above the feet), sigma a fixed fraction of
  the person's full (amodal) height, so near and far people look alike relative to their size.
* Keypoints: a Gaussian per labelled keypoint (visible or occluded; unlabelled ones get nothing), sigma a smaller
  fraction of the height; left/right pairs in image order (:mod:`vc.deploy.heatmaps` says why), as the
  annotation's ``left_is_image_left`` (one flag per pair, from the person's 3-D keypoints) sorts them.
* Mask: the fraction of each cell covered by people (area average of the instance mask).
* Handedness: per pair, +1 (left is image-left) or -1 times the fraction of each cell covered by that person
  (its ``instance_id`` in the instance mask); 0 elsewhere. Annotations without the flags get no handedness and
  keep their pairs in anatomical order.
* Centre offsets (with ``centre_offsets``): over each cell that people cover, the (x, y) from the cell to the
  centre of the person covering most of it, in that person's heights; 0 elsewhere. The loss weighs them by the
  mask, which is 0 where they mean nothing (:mod:`vc.model.loss`).
* Fine centre (with ``fine_centre``, on top of the offsets): the centre Gaussians again, same sigma in input pixels,
  on a grid of twice the resolution, stored space-to-depth (:data:`vc.deploy.heatmaps.FINE_CENTRE_CHANNELS`).
* Head and size (with ``head_map``, on top of the fine centre): a Gaussian at each person's head (:func:`head_point`),
  sigma ``head_sigma`` of their height, and over each cell that people cover, log(height / SIZE_UNIT_CELLS) of the
  person covering most of it (:data:`vc.deploy.heatmaps.HEAD_CHANNEL`, :data:`~vc.deploy.heatmaps.SIZE_CHANNEL`).
  The loss weighs the size by the mask, as the offsets.

Several people combine by maximum (Gaussians) so that neighbours do not merge into one peak. Decoding lives in
:mod:`vc.deploy.decode` and uses the same cell geometry (:mod:`vc.deploy.heatmaps`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from vc.calibration.camera import Camera
from vc.deploy.heatmaps import (
    CENTRE_CHANNEL,
    CENTRE_OFFSET_CHANNELS,
    FINE_CENTRE_CHANNELS,
    FINE_CHANNELS,
    FINE_FACTOR,
    HANDEDNESS_CHANNELS,
    HEAD_CHANNEL,
    HEAD_CHANNELS,
    HEATMAP_CHANNELS,
    KEYPOINT_CHANNELS,
    MASK_CHANNEL,
    OFFSET_CHANNELS,
    PAIRS,
    SIZE_CHANNEL,
    SIZE_UNIT_CELLS,
    cells_to_fine,
    cells_to_input,
    fine_centre_channels,
    input_to_cells,
    swap_pairs,
)
from vc.keypoints import COCO_KEYPOINTS

#: Gaussians are drawn out to this many sigmas (beyond, exp(-x^2/2) < 1.2e-4).
TRUNCATE_SIGMAS = 4.25
#: The keypoints whose middle is a person's head: nose, eyes and ears.
FACE_KEYPOINTS = tuple(COCO_KEYPOINTS.index(name) for name in
                       ("nose", "left_eye", "right_eye", "left_ear", "right_ear"))


@dataclass(frozen=True)
class CodecConfig:
    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    stride: int = 4  # output stride of the network
    centre_sigma: float = 0.08  # centre Gaussian sigma, as a fraction of the person's height (input px)
    keypoint_sigma: float = 0.025  # keypoint Gaussian sigma, as a fraction of the person's height
    min_sigma_cells: float = 0.75  # no Gaussian narrower than this many cells (tiny people stay learnable)
    # Also draw the centre-offset maps (vc.deploy.heatmaps.CENTRE_OFFSET_CHANNELS); the network then emits them.
    centre_offsets: bool = False
    # Also draw the centre map at twice the resolution (vc.deploy.heatmaps.FINE_CENTRE_CHANNELS; with the offsets).
    fine_centre: bool = False
    # Also draw the head and size maps (vc.deploy.heatmaps.HEAD_CHANNEL, SIZE_CHANNEL; with the fine centre map).
    head_map: bool = False
    # The head Gaussian's sigma, as a fraction of the person's height: a head is about an eighth of it, and heads
    # in a group stand about a tenth of a height apart.
    head_sigma: float = 0.05

    def __post_init__(self) -> None:
        if self.fine_centre and not self.centre_offsets:
            raise ValueError("the fine centre map comes after the centre offsets in the layout: set centre_offsets")
        if self.head_map and not self.fine_centre:
            raise ValueError("the head and size maps come after the fine centre map in the layout: set fine_centre")

    @property
    def channels(self) -> int:
        """The number of maps :func:`encode` draws: the network's output layout."""
        return (HEAD_CHANNELS if self.head_map else FINE_CHANNELS if self.fine_centre
                else OFFSET_CHANNELS if self.centre_offsets else HEATMAP_CHANNELS)

    def to_dict(self) -> dict:
        return asdict(self)


def _draw_gaussians(heatmaps: np.ndarray, channels: np.ndarray, centres: np.ndarray, sigmas: Sequence[float]) -> None:
    """Max-combine a unit-peak Gaussian (cell units) into each of the maps ``heatmaps[channels]`` ((K,) of
    (C, h, w)) at its centre (K, 2), of its sigma (K,), truncated to its support. The K Gaussians are evaluated
    and combined in one call: the loader's time is the training step's on a CPU, and a window holds a dozen people
    of a dozen maps each. Each value is the one the Gaussian would draw alone."""
    _, height, width = heatmaps.shape
    if not len(centres):
        return
    sigmas = np.asarray(sigmas, np.float64)
    # Python floats squared as ever (pow, where numpy squares by multiplying), so the targets keep their bytes.
    denominators = np.array([2.0 * float(sigma) ** 2 for sigma in sigmas])
    reach = TRUNCATE_SIGMAS * sigmas
    x0, y0 = np.floor(centres[:, 0] - reach).astype(int), np.floor(centres[:, 1] - reach).astype(int)
    x1, y1 = np.ceil(centres[:, 0] + reach).astype(int) + 1, np.ceil(centres[:, 1] + reach).astype(int) + 1
    size = int(max((x1 - x0).max(), (y1 - y0).max()))
    columns, rows = x0[:, None] + np.arange(size), y0[:, None] + np.arange(size)  # (K, size): each window's cells
    xs, ys = columns - centres[:, 0, None], rows - centres[:, 1, None]  # minus the centre
    # Each Gaussian's own support inside the maps (the cells it would have drawn alone), and its values there.
    inside = ((rows >= np.maximum(y0, 0)[:, None]) & (rows < np.minimum(y1, height)[:, None]))[:, :, None] & (
        (columns >= np.maximum(x0, 0)[:, None]) & (columns < np.minimum(x1, width)[:, None]))[:, None, :]
    drawn, row, column = np.nonzero(inside)
    values = np.exp(-(ys[drawn, row] ** 2 + xs[drawn, column] ** 2) / denominators[drawn]).astype(np.float32)
    np.maximum.at(heatmaps, (np.asarray(channels)[drawn], rows[drawn, row], columns[drawn, column]), values)


def person_height_px(annotation: dict) -> float:
    """The person's full height in input pixels (occluded and cut-off parts included)."""
    return float(annotation["amodal_bbox"][3])


def head_point(annotation: dict) -> np.ndarray:
    """(x, y) input px: the middle of the person's labelled nose, eyes and ears, seen or hidden (the head is where
    it is whether or not a neighbour covers it); the centre where none is labelled."""
    face = np.reshape(annotation["keypoints"], (-1, 3))[list(FACE_KEYPOINTS)]
    labelled = face[face[:, 2] > 0]
    return labelled[:, :2].mean(axis=0) if len(labelled) else np.array(annotation["center"], float)


def encode(annotations: list[dict], instances: np.ndarray, config: CodecConfig = CodecConfig()) -> np.ndarray:
    """Heat maps (config.channels, H/stride, W/stride) float32 for one sample: its annotations and (H, W)
    instance mask. Each kind of map is drawn for everyone at once (the loader's time is the step's on a CPU)."""
    height, width = instances.shape
    stride = config.stride
    if height % stride or width % stride:
        raise ValueError(f"input {width}x{height} is not a multiple of the output stride {stride}")
    cells = (height // stride, width // stride)
    heatmaps = np.zeros((config.channels, *cells), np.float32)
    sizes = [person_height_px(annotation) / stride for annotation in annotations]  # heights in cells
    centred = [k for k, annotation in enumerate(annotations) if annotation.get("center") is not None]
    if centred:
        centres = input_to_cells([annotations[k]["center"] for k in centred], stride)
        _draw_gaussians(heatmaps, np.full(len(centred), CENTRE_CHANNEL), centres,
                        [max(config.centre_sigma * sizes[k], config.min_sigma_cells) for k in centred])
        if config.fine_centre:
            fine = np.zeros((1, FINE_FACTOR * cells[0], FINE_FACTOR * cells[1]), np.float32)
            _draw_gaussians(fine, np.zeros(len(centred), int), cells_to_fine(centres),
                            [max(config.centre_sigma * sizes[k] * FINE_FACTOR, config.min_sigma_cells)
                             for k in centred])
            heatmaps[FINE_CENTRE_CHANNELS] = fine_centre_channels(fine[0])
        if config.head_map:
            _draw_gaussians(heatmaps, np.full(len(centred), HEAD_CHANNEL),
                            input_to_cells([head_point(annotations[k]) for k in centred], stride),
                            [max(config.head_sigma * sizes[k], config.min_sigma_cells) for k in centred])
    if annotations:
        _draw_keypoints(heatmaps, annotations, sizes, config)
    cell_of_pixel = (np.arange(height)[:, None] // stride * cells[1] + np.arange(width) // stride).ravel()
    heatmaps[MASK_CHANNEL] = _cell_shares(cell_of_pixel[(instances > 0).ravel()], cells, stride)
    handed = [annotation.get("left_is_image_left") is not None for annotation in annotations]
    if not (config.centre_offsets or any(handed)):
        return heatmaps
    shares = _people_shares(annotations, instances, cell_of_pixel, cells, stride)  # each person's share of each cell
    for annotation, share, flagged in zip(annotations, shares, handed, strict=True):
        if flagged:
            sign = np.where(annotation["left_is_image_left"], 1.0, -1.0).astype(np.float32)
            heatmaps[HANDEDNESS_CHANNELS] += share[None] * sign[:, None, None]
    if config.centre_offsets:
        _draw_centre_offsets(heatmaps[CENTRE_OFFSET_CHANNELS], [annotations[k] for k in centred], shares[centred],
                             stride)
    if config.head_map:
        _draw_sizes(heatmaps[SIZE_CHANNEL], annotations, shares, stride)
    return heatmaps


def _draw_keypoints(heatmaps: np.ndarray, annotations: list[dict], sizes: list[float], config: CodecConfig) -> None:
    """Everyone's labelled keypoints, image-ordered where the annotation says how (:func:`swap_pairs`), each
    person's Gaussians of their own sigma."""
    keypoints = np.array([annotation["keypoints"] for annotation in annotations], np.float64).reshape(
        len(annotations), -1, 3)
    flags = [annotation.get("left_is_image_left") for annotation in annotations]
    keypoints = swap_pairs(keypoints, [np.logical_not(flag) if flag is not None else np.zeros(len(PAIRS), bool)
                                       for flag in flags])
    people, labelled = np.nonzero(keypoints[:, :, 2] > 0)
    sigmas = [max(config.keypoint_sigma * size, config.min_sigma_cells) for size in sizes]
    _draw_gaussians(heatmaps, KEYPOINT_CHANNELS.start + labelled,
                    input_to_cells(keypoints[people, labelled, :2], config.stride), [sigmas[k] for k in people])


def _cell_shares(cell_of_pixel: np.ndarray, cells: tuple[int, int], stride: int) -> np.ndarray:
    """(h, w) float32: the share of each cell's stride x stride pixels among ``cell_of_pixel`` (flat cell indices,
    one a pixel), as the mean over the cell's pixels gives it."""
    counts = np.bincount(cell_of_pixel, minlength=cells[0] * cells[1])
    return (counts.astype(np.float32) / np.float32(stride * stride)).reshape(cells)


def _people_shares(annotations: list[dict], instances: np.ndarray, cell_of_pixel: np.ndarray,
                   cells: tuple[int, int], stride: int) -> np.ndarray:
    """(N, h, w) float32: each annotation's share of each cell (its ``instance_id``'s pixels), in one pass over the
    instance mask."""
    ids = np.array([annotation["instance_id"] for annotation in annotations], np.int64)
    lookup = np.full(max(int(instances.max(initial=0)), int(ids.max(initial=0))) + 1, len(annotations), np.int64)
    lookup[ids] = np.arange(len(annotations))
    person = lookup[instances].ravel()  # each pixel's annotation; len(annotations) for nobody's
    ours = person < len(annotations)
    counts = np.bincount(person[ours] * (cells[0] * cells[1]) + cell_of_pixel[ours],
                         minlength=len(annotations) * cells[0] * cells[1])
    return (counts.astype(np.float32) / np.float32(stride * stride)).reshape(len(annotations), *cells)


def _draw_centre_offsets(offsets: np.ndarray, centred: list[dict], shares: np.ndarray, stride: int) -> None:
    """Fill ``offsets`` (2, h, w): at each cell, (centre - cell) / height (cells) of the person who covers most of
    it, among the ``centred`` annotations (``shares``: each one's share of each cell). People without a centre (none
    projected) cover their cells without an offset to learn (0, as off people)."""
    if not centred:
        return
    owner = shares.argmax(axis=0)
    owned = shares.max(axis=0) > 0
    centres = input_to_cells(np.array([annotation["center"] for annotation in centred]), stride)  # (N, 2)
    heights = np.array([person_height_px(annotation) / stride for annotation in centred])  # (N,)
    rows, columns = np.nonzero(owned)
    people = owner[rows, columns]
    offsets[0, rows, columns] = (centres[people, 0] - columns) / heights[people]
    offsets[1, rows, columns] = (centres[people, 1] - rows) / heights[people]


def _draw_sizes(sizes: np.ndarray, annotations: list[dict], shares: np.ndarray, stride: int) -> None:
    """Fill ``sizes`` (h, w): at each cell, log(height / SIZE_UNIT_CELLS) (cells) of the person who covers most of
    it (``shares``: each annotation's share of each cell); 0 where nobody does (the loss does not weigh those
    cells)."""
    if not annotations:
        return
    owner, owned = shares.argmax(axis=0), shares.max(axis=0) > 0
    logs = np.log(np.array([person_height_px(annotation) / stride for annotation in annotations]) / SIZE_UNIT_CELLS)
    sizes[owned] = logs[owner[owned]]


def expected_height_map(camera: Camera, stride: int, height_m: float) -> np.ndarray:
    """(h, w) float32: the input-pixel height of a ``height_m`` person whose centre lies at each heat-map cell of
    ``camera``'s input (the decoder's scene-specific box height). Cells where no one can stand get the nearest
    valid value along their column (their peaks are spurious anyway; the box stays finite)."""
    cells = (camera.height // stride, camera.width // stride)
    rows, columns = np.indices(cells)
    centres = cells_to_input(np.stack([columns, rows], axis=-1), stride)
    heights = camera.person_height_at_centres(centres, height_m)
    for column in range(cells[1]):
        valid = np.isfinite(heights[:, column])
        if not valid.any():
            heights[:, column] = np.nanmedian(heights) if np.isfinite(heights).any() else camera.height
        elif not valid.all():
            heights[~valid, column] = heights[valid, column][np.abs(np.nonzero(valid)[0][:, None]
                                                                   - np.nonzero(~valid)[0][None]).argmin(axis=0)]
    return heights.astype(np.float32)
