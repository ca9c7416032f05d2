"""Decoding a network whose centre map peaks at each person's visible centroid or head (frozen experiment, issue 57
item 2).

Step 1 of :mod:`vc.deploy.decode` changes in two ways, everything after it is today's: peaks closer than the centre
separation are merged among the peaks themselves (the visible anchors, which people in groups keep apart), and each
kept peak becomes the person's centre by the centre offsets at its cell (which point to the amodal centre, half the
stature above the feet, that the rest of the decoder and its expected heights are built on).

``install()`` puts it in place of the decoder for the runtime (numpy decoder), held-out evaluation and scripts that
call ``vc.deploy.decode.decode``.
"""

from __future__ import annotations

import dataclasses
import threading
from contextlib import contextmanager

import numpy as np

import vc.deploy.decode as decoding
import vc.deploy.native as native
import vc.deploy.runtime as runtime
import vc.model.held_out as held_out
from vc.deploy.heatmaps import CENTRE_OFFSET_CHANNELS, FINE_CENTRE_CHANNELS, cells_to_input

_ORIGINAL_DECODE = decoding.decode
_ORIGINAL_FIND_PEAKS = decoding.find_peaks
_ORIGINAL_SEPARATED = decoding._separated
_state = threading.local()
#: The heat maps' (h, w) decoded this way (None: all): the regions whose network peaks at the visible centroid.
_VISIBLE_SHAPES: set[tuple[int, int]] | None = None
#: The anchors' separation (person heights; None: the config's ``min_centre_separation``).
_SEPARATION: list[float | None] = [None]
#: The centre offsets' unit in cells (None: the height of the person they point to, as the codec draws them).
_OFFSET_UNIT: list[float | None] = [None]
#: With a unit (cells), the fine map's first channel is each person's log height in it (``anchors.py --size-unit``).
_SIZE_UNIT: list[float | None] = [None]
SIZE_CHANNEL = FINE_CENTRE_CHANNELS.start
#: The size map's box only where the decoder's box height differs from it by more than this share (None: always).
_SIZE_AGREEMENT: list[float | None] = [None]
#: Whether step 1b's votes may add people (``install(..., voted_people=False)``: they only move peaks).
_NO_VOTED_PEOPLE = [False]


def decode(heatmaps, config=None, expected_height_px=None, weak_above=None, prior=decoding.UPRIGHT_PRIOR):
    config = decoding.DecodeConfig() if config is None else config
    if _NO_VOTED_PEOPLE[0]:
        config = dataclasses.replace(config, vote_support=float("inf"))  # step 1b adds nobody
    visible = (getattr(_state, "forced", False) or _VISIBLE_SHAPES is None
               or tuple(heatmaps.shape[1:]) in _VISIBLE_SHAPES)
    if visible and _OFFSET_UNIT[0] is not None:
        heatmaps = _offsets_in_heights(heatmaps, config, expected_height_px)
    _state.args = (heatmaps, config, expected_height_px) if visible else None
    _state.sizes = {}
    try:
        people = _ORIGINAL_DECODE(heatmaps, config, expected_height_px, weak_above, prior)
    finally:
        _state.args = None
    return [_sized(person, config.stride) for person in people] if visible and _SIZE_UNIT[0] is not None else people


def _sized(person, stride: int):
    """``person`` with their box's top and bottom at their centre -+ half the height the size map read at their
    anchor (people step 1b added or moved keep the decoder's box)."""
    height = _state.sizes.get(tuple(np.round(person.centre, 3)))
    if height is None:
        return person
    decoded = person.box[3] - person.box[1]
    if _SIZE_AGREEMENT[0] is not None and abs(np.log(decoded / height)) <= np.log1p(_SIZE_AGREEMENT[0]):
        return person  # the decoder's box (its own head and ankles) agrees with the size: it is the finer
    box = person.box.copy()
    box[1], box[3] = person.centre[1] - height / 2, person.centre[1] + height / 2
    return dataclasses.replace(person, box=box)


def _offsets_in_heights(heatmaps: np.ndarray, config, expected: np.ndarray | None) -> np.ndarray:
    """Offsets drawn in :data:`_OFFSET_UNIT` cells rescaled so that the decoder, which multiplies each cell's offset
    by the expected height there, gets cell + offset x unit back; the anchors read ``offset_unit`` cells per unit."""
    heights = (np.full(heatmaps.shape[1:], config.default_height_px) if expected is None else expected) / config.stride
    scaled = heatmaps.copy()
    scaled[CENTRE_OFFSET_CHANNELS] *= (_OFFSET_UNIT[0] / np.maximum(heights, 1e-6))[None]
    return scaled


def _heights_cells(xy_cells: np.ndarray, config, expected: np.ndarray | None, shape: tuple[int, int]) -> np.ndarray:
    if expected is None:
        return np.full(len(xy_cells), config.default_height_px / config.stride)
    rows = np.clip(np.round(xy_cells[:, 1]).astype(int), 0, shape[0] - 1)
    columns = np.clip(np.round(xy_cells[:, 0]).astype(int), 0, shape[1] - 1)
    return expected[rows, columns].astype(float) / config.stride


def _find_peaks(heatmap, threshold, limit=None):
    peaks = _ORIGINAL_FIND_PEAKS(heatmap, threshold, limit)
    args = getattr(_state, "args", None)
    if args is None or not peaks:
        return peaks
    maps, config, expected = args
    shape = heatmap.shape
    anchors = np.array([centre for _, centre in peaks]).reshape(-1, 2)
    rows = np.clip(np.round(anchors[:, 1]).astype(int), 0, shape[0] - 1)
    columns = np.clip(np.round(anchors[:, 0]).astype(int), 0, shape[1] - 1)
    heights = (_SIZE_UNIT[0] * np.exp(maps[SIZE_CHANNEL, rows, columns]) if _SIZE_UNIT[0] is not None
               else _heights_cells(anchors, config, expected, shape))  # a head's own size where it has one
    default = 0.0 if _SIZE_UNIT[0] is not None else config.min_centre_separation  # heads stand apart
    keep = _ORIGINAL_SEPARATED(anchors, heights, default if _SEPARATION[0] is None else _SEPARATION[0])
    anchors, rows, columns = anchors[keep], rows[keep], columns[keep]
    offsets = maps[CENTRE_OFFSET_CHANNELS][:, rows, columns].T  # (N, 2) person heights
    centres = np.array([_centre_from(anchor, offset, config, expected, shape)
                        for anchor, offset in zip(anchors, offsets, strict=True)]).reshape(-1, 2)
    centres = np.clip(centres, 0, [shape[1] - 1, shape[0] - 1])  # the decoder reads maps at its centres
    if _SIZE_UNIT[0] is not None:
        heights_px = _SIZE_UNIT[0] * config.stride * np.exp(maps[SIZE_CHANNEL, rows, columns])
        _state.sizes = {tuple(np.round(cells_to_input(centre[None], config.stride)[0], 3)): height
                        for centre, height in zip(centres, heights_px, strict=True)}
    return [(peaks[index][0], centre) for index, centre in zip(keep, centres, strict=True)]


def _centre_from(anchor: np.ndarray, offset: np.ndarray, config, expected: np.ndarray | None,
                 shape: tuple[int, int]) -> np.ndarray:
    """The centre C = anchor + offset x H(C) (cells), H the expected height of a person centred at C (with offsets in
    :data:`_OFFSET_UNIT`, their offset read back to that unit at the anchor's cell, the same sum): the offsets
    are in the heights of the person they point to, whose height is known where their centre is, not at the anchor
    (a head at an eye-level camera's horizon would read a person at infinity). Solved along the anchor's column,
    each row's H read there; its x follows."""
    if _OFFSET_UNIT[0] is not None:  # the heat maps were rescaled by the anchor's cell's expected height
        row, column = (int(np.clip(np.round(anchor[1]), 0, shape[0] - 1)),
                       int(np.clip(np.round(anchor[0]), 0, shape[1] - 1)))
        here = config.default_height_px if expected is None else float(expected[row, column])
        return anchor + offset * here / config.stride
    if expected is None:
        return anchor + offset * config.default_height_px / config.stride
    column = int(np.clip(np.round(anchor[0]), 0, shape[1] - 1))
    rows = np.arange(shape[0], dtype=float)
    heights = expected[:, column].astype(float) / config.stride
    residual = rows - anchor[1] - offset[1] * heights
    best = int(np.argmin(np.abs(residual)))
    return np.array([anchor[0] + offset[0] * heights[best], anchor[1] + offset[1] * heights[best]])


def _separated(centres_cells, heights_cells, separation):
    if getattr(_state, "args", None) is not None:
        return list(range(len(centres_cells)))  # separated among the anchors already
    return _ORIGINAL_SEPARATED(centres_cells, heights_cells, separation)


@contextmanager
def anchored():
    """Within it, every heat map is decoded as an anchored network's (on this thread)."""
    _state.forced = True
    try:
        yield
    finally:
        _state.forced = False


def install(shapes: set[tuple[int, int]] | None = None, separation: float | None = None,
            offset_unit: float | None = None, size_unit: float | None = None, voted_people: bool = True,
            size_agreement: float | None = None) -> None:
    """Decode heat maps of these (h, w) shapes (None: every one; see also :func:`anchored`) as an anchored
    network's (its peaks at the visible centroid or the head), peaks closer than ``separation`` heights (None: the
    config's) one person's, its offsets in ``offset_unit`` cells (None: in heights), its boxes' heights from its size
    map in ``size_unit`` cells (None: the decoder's; with it, peaks are separated in those heights, by nothing unless
    ``separation`` says), and without
    ``voted_people`` step 1b adds nobody (every decoding, anchored or not); with ``size_agreement`` the decoder's box
    stays where its height is within that share of the size map's."""
    global _VISIBLE_SHAPES
    _VISIBLE_SHAPES = shapes
    _SEPARATION[0] = separation
    _OFFSET_UNIT[0] = offset_unit
    _SIZE_UNIT[0] = size_unit
    _NO_VOTED_PEOPLE[0] = not voted_people
    _SIZE_AGREEMENT[0] = size_agreement
    decoding.find_peaks = _find_peaks
    decoding._separated = _separated
    decoding.decode = runtime.decode = held_out.decode = decode
    native.default_decoder = lambda: "numpy"
