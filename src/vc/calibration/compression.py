"""JPEG-like block compression: find the quality a camera's images were last compressed at, and apply it.

Images here are RGB uint8 (OpenCV's codec works in BGR: :func:`jpeg_round_trip` converts). Block grids are
anchored at pixel (0, 0), as an encoder places them on a whole frame: 8 x 8 for luma, 16 x 16 for 4:2:0 chroma.
A crop that starts off that grid hides the compression from :func:`estimate_jpeg`, which then reports none.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

#: Qualities the estimate tries (OpenCV's scale: 100 is the finest quantisation).
QUALITIES = np.arange(5, 101)
#: The estimate recompresses a central crop at most this large (pixels, a multiple of 16 to keep both grids).
CROP = 384
#: A quality is the one the image was compressed at when recompressing there changes the luma at most this
#: share of what its neighbours (up to :data:`NEIGHBOURS` qualities either side) change it by.
MAX_DIP_RATIO = 0.5
NEIGHBOURS = 5
#: ... and the neighbours change it by at least this much (mean squared 8-bit levels).
MIN_NEIGHBOUR_CHANGE = 0.1
#: The ghost needs detail inside the blocks: a crop whose luma varies less than this (8-bit levels, standard
#: deviation inside 8 x 8 blocks, averaged) only moves its block means, and shows no quality.
MIN_BLOCK_DETAIL = 1.0


@dataclass(frozen=True)
class JpegEstimate:
    """``quality`` the image was last JPEG-compressed at (OpenCV's scale), or None when no compression was found;
    ``chroma_subsampling``: 4:2:0 chroma; ``evidence``: the measurements behind both, for reports."""

    quality: int | None
    chroma_subsampling: bool
    evidence: dict = field(default_factory=dict)


def _rgb(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {image.dtype} {image.shape}")
    return image


def jpeg_round_trip(image: np.ndarray, quality: int, chroma_subsampling: bool) -> np.ndarray:
    """``image`` (RGB uint8) compressed as JPEG at ``quality`` (1..100) with 4:2:0 or 4:4:4 chroma, and decoded."""
    sampling = cv2.IMWRITE_JPEG_SAMPLING_FACTOR_420 if chroma_subsampling else cv2.IMWRITE_JPEG_SAMPLING_FACTOR_444
    bgr = np.ascontiguousarray(_rgb(image)[..., ::-1])
    ok, encoded = cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, int(quality),
                                             cv2.IMWRITE_JPEG_SAMPLING_FACTOR, sampling])
    if not ok:
        raise RuntimeError(f"OpenCV could not JPEG-encode a {image.shape} image at quality {quality}")
    return cv2.imdecode(encoded, cv2.IMREAD_COLOR)[..., ::-1]


def _ycrcb(image: np.ndarray) -> np.ndarray:
    """JPEG's own colour space (BT.601 full range), float32."""
    return cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_RGB2YCrCb).astype(np.float32)


def blockiness(image: np.ndarray) -> float:
    """Mean luma step across 8-pixel block boundaries over the mean step inside blocks (rows and columns pooled):
    about 1.0 for an image never block-compressed, above it for visible blocking. 1.0 when there is nothing to
    compare (an image narrower than two blocks, or flat inside its blocks)."""
    luma = _ycrcb(_rgb(image))[..., 0]
    across, inside = [], []
    for steps in (np.abs(np.diff(luma, axis=1)), np.abs(np.diff(luma, axis=0)).T):
        boundary = (np.arange(steps.shape[1]) + 1) % 8 == 0
        across.append(steps[:, boundary].ravel())
        inside.append(steps[:, ~boundary].ravel())
    across_mean, inside_mean = np.concatenate(across), np.concatenate(inside)
    if across_mean.size == 0 or inside_mean.size == 0 or inside_mean.mean() == 0.0:
        return 1.0
    return float(across_mean.mean() / inside_mean.mean())


def estimate_jpeg(image: np.ndarray) -> JpegEstimate:
    """The quality ``image`` (RGB uint8) was last JPEG-compressed at, and whether its chroma was 4:2:0.

    Method: the JPEG ghost (Farid, "Exposing digital forgeries from JPEG ghosts", 2009). Recompressing an image
    at the quality it was compressed at leaves it almost unchanged — its DCT coefficients already sit on that
    quantiser's steps — while any other quality moves them; the mean squared luma change over qualities 5..100
    has a sharp dip there. An uncompressed image (a render, a temporal median) changes less and less up to 100,
    without a dip, and gets None; so do images compressed at 98 or finer, whose quantiser steps are 1 or 2 and
    leave nothing to see. Chosen over reading quantisation steps off DCT histograms because it asks the question
    :func:`jpeg_round_trip` needs answered — at which of OpenCV's qualities is this image a fixed point — with
    no table fitting, and holds for any encoder that uses the standard tables scaled by quality.

    Chroma: at the quality found, the image is recompressed with 4:2:0 and with 4:4:4 chroma; the one that
    changes the chroma less is the one it was compressed with. Works on a central crop of at most
    :data:`CROP` pixels on the 16-pixel grid (recompressing costs ~1 ms a quality there)."""
    image = _rgb(image)
    height, width = (min(CROP, size // 16 * 16) for size in image.shape[:2])
    evidence: dict = {"blockiness": round(blockiness(image), 4)}
    if height == 0 or width == 0:
        return JpegEstimate(None, False, evidence | {"reason": "smaller than one 16 x 16 block"})
    top, left = (image.shape[0] - height) // 2 // 16 * 16, (image.shape[1] - width) // 2 // 16 * 16
    crop = np.ascontiguousarray(image[top : top + height, left : left + width])
    original = _ycrcb(crop)
    blocks = original[..., 0].reshape(height // 8, 8, width // 8, 8)
    evidence["block_detail"] = round(float(blocks.std(axis=(1, 3)).mean()), 3)
    if evidence["block_detail"] < MIN_BLOCK_DETAIL:
        return JpegEstimate(None, False, evidence | {"reason": "too flat to show a quality"})
    change = np.array([np.mean((_ycrcb(jpeg_round_trip(crop, quality, False))[..., 0] - original[..., 0]) ** 2)
                       for quality in QUALITIES])
    # Each quality's change over its neighbours' (the largest on each side, the smaller of the two sides: tables of
    # adjacent qualities can be alike; the coarsest quality has only one side). The finest quality is a fixed
    # point of every image (steps of 1): it is a neighbour, never the answer.
    padded = np.concatenate([np.full(NEIGHBOURS, -np.inf), change, np.full(NEIGHBOURS, -np.inf)])
    windows = np.lib.stride_tricks.sliding_window_view(padded, NEIGHBOURS)
    before, after = windows[: change.size].max(axis=1), windows[NEIGHBOURS + 1 :].max(axis=1)
    neighbours = np.minimum(np.where(np.isneginf(before), np.inf, before), after)[:-1]
    ratio = np.where(neighbours >= MIN_NEIGHBOUR_CHANGE, change[:-1] / np.maximum(neighbours, MIN_NEIGHBOUR_CHANGE),
                     np.inf)
    best = int(np.argmin(ratio))
    evidence |= {"ghost_quality": int(QUALITIES[best]), "ghost_luma_mse": round(float(change[best]), 5),
                 "ghost_dip_ratio": round(float(ratio[best]), 4) if np.isfinite(ratio[best]) else None}
    if ratio[best] > MAX_DIP_RATIO:
        return JpegEstimate(None, False, evidence)
    quality = int(QUALITIES[best])
    chroma = {subsampled: float(np.mean((_ycrcb(jpeg_round_trip(crop, quality, subsampled))[..., 1:]
                                         - original[..., 1:]) ** 2)) for subsampled in (True, False)}
    evidence |= {"chroma_mse_420": round(chroma[True], 5), "chroma_mse_444": round(chroma[False], 5)}
    return JpegEstimate(quality, chroma[True] < chroma[False], evidence)


#: Qualities :func:`equivalent_quality` tries, coarsest first.
EQUIVALENT_QUALITIES = tuple(range(5, 100, 5))


def equivalent_quality(clean: np.ndarray, target_blockiness: float, chroma_subsampling: bool = True) -> int | None:
    """The JPEG quality at which ``clean`` (RGB uint8, not yet compressed) shows ``target_blockiness``: the finest
    of :data:`EQUIVALENT_QUALITIES` that blocks it at least that much. For frames of a video codec, whose
    motion-compensated quantiser is not idempotent the way JPEG's is (no ghost), this matches the visible blocking
    instead of the quantiser. None when even the finest quality tried blocks it more than the target."""
    clean = _rgb(clean)
    found = None
    for quality in EQUIVALENT_QUALITIES:
        if blockiness(jpeg_round_trip(clean, quality, chroma_subsampling)) >= target_blockiness:
            found = quality
        else:
            break
    return found
