"""Optical blur: how blurred a camera's strong edges are, as one Gaussian sigma, and blurring by one.

Sigmas are in pixels of the image measured (full-frame camera pixels for a background). "Blur" is everything
between the scene and the stored pixel that spreads an edge — lens, sensor pixel area, demosaicing, resampling —
summed as a Gaussian would: a box-filtered render's own pixels carry 1/sqrt(12) px of it.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import cv2
import numpy as np
from scipy import ndimage

#: Scale of the gradient operator: a Gaussian of this sigma, then central differences, whose own spread adds
#: the variance of :data:`GRADIENT_VARIANCE` to every edge measured.
GRADIENT_SIGMA = 1.0
#: Central differences (-1, 0, 1) / 2 act on an edge like a Gaussian of variance 1/3 (their frequency response
#: is sin(w)/w ~ 1 - w²/6).
GRADIENT_VARIANCE = GRADIENT_SIGMA**2 + 1.0 / 3.0
#: Known blur the image is re-blurred with; 2 px keeps the gradient ratio well away from 1 for sharp edges
#: without merging edges a few pixels apart.
REBLUR_SIGMA = 2.0
#: Edges are used when their step is at least this many 8-bit levels of luma: weaker ones are texture, whose
#: fine detail (not the optics) sets their gradient profile, and noise moves them most.
MIN_CONTRAST = 20.0
#: Pixels of the border left out (the blurs' reach) and around clipped pixels (a clipped edge looks sharp).
MARGIN = int(np.ceil(3.0 * (REBLUR_SIGMA + GRADIENT_SIGMA)))
#: Rec. 709 luma weights, on the encoded values.
_LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)


@dataclass(frozen=True)
class BlurEstimate:
    """The Gaussian ``sigma_px`` that describes the image's strong edges, measured on ``edges`` edge pixels
    (0 and 0.0 when the image shows no edge strong enough)."""

    sigma_px: float
    edges: int

    def to_dict(self) -> dict:
        return asdict(self)


def gaussian_blur(image: np.ndarray, sigma: float) -> np.ndarray:
    """``image`` (H, W) or (H, W, C), float, blurred by a Gaussian of ``sigma`` pixels (reflected borders); sigma 0
    returns an unchanged copy. Any number of channels (OpenCV filters at most 512 at a time)."""
    if sigma < 0.0:
        raise ValueError(f"blur sigma must be >= 0, got {sigma}")
    image = np.asarray(image)
    if sigma == 0.0 or image.size == 0:
        return image.copy()
    if image.ndim == 2:
        return cv2.GaussianBlur(image, (0, 0), sigma, borderType=cv2.BORDER_REFLECT)
    chunks = [cv2.GaussianBlur(np.ascontiguousarray(image[..., start : start + 512]), (0, 0), sigma,
                               borderType=cv2.BORDER_REFLECT).reshape(*image.shape[:2], -1)
              for start in range(0, image.shape[2], 512)]
    return np.concatenate(chunks, axis=2)


def added_blur(target_sigma: float, existing_sigma: float) -> float:
    """The Gaussian that takes an image blurred by ``existing_sigma`` to ``target_sigma`` (Gaussian variances
    add); 0 when it is already at least as blurred."""
    return float(np.sqrt(max(target_sigma**2 - existing_sigma**2, 0.0)))


def _gradient(luma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    smooth = cv2.GaussianBlur(luma, (0, 0), GRADIENT_SIGMA, borderType=cv2.BORDER_REFLECT)
    return (cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=1, scale=0.5),
            cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=1, scale=0.5))


def estimate_blur_sigma(image: np.ndarray) -> BlurEstimate:
    """The Gaussian sigma (pixels) of the blur on ``image``'s (RGB uint8) strong edges.

    Method: the re-blur gradient ratio (Zhuo & Sim, "Defocus map estimation from a single image", 2011). A step
    edge blurred by ``s`` has a gradient peak of ``A / (sqrt(2 pi) s)``; re-blurred by a known ``s0`` its peak
    drops by ``R = sqrt(s² + s0²) / s``, so ``s² = s0² / (R² - 1)``. Here ``s`` includes the gradient operator's
    own spread (:data:`GRADIENT_VARIANCE`), which is subtracted. Edge pixels are the gradient's maxima across the
    edge (Canny's non-maximum suppression, without its hysteresis: the contrast threshold replaces it); both
    gradients are read at the edge pixel itself (an edge between pixel centres lowers both peaks nearly alike).
    An edge is used when its step ``A`` (recovered from the same two peaks) is at least :data:`MIN_CONTRAST`,
    away from the border and from clipped pixels. On ideal edges this reads blurs of 0.4 to 2.5 px within
    0.04 px; below about 0.4 px the pixel grid, not the optics, sets the gradient, and a box-filtered render's
    own 0.29 px reads as about 0.43.

    The answer is the median over those edges. A low quantile would look for the sharpest, in-focus edges, but
    the method's own errors (thin lines and edges a few pixels apart read sharper than they are) sit in the low
    tail; a surveillance camera is focused over its whole ground range, so most strong edges share its blur."""
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {image.dtype} {image.shape}")
    height, width = image.shape[:2]
    if min(height, width) <= 2 * MARGIN:
        return BlurEstimate(0.0, 0)
    luma = image.astype(np.float32) @ _LUMA
    gx, gy = _gradient(luma)
    magnitude = np.hypot(gx, gy)
    reblurred = np.hypot(*_gradient(cv2.GaussianBlur(luma, (0, 0), REBLUR_SIGMA, borderType=cv2.BORDER_REFLECT)))

    # Candidates: gradient strong enough for a MIN_CONTRAST step spread up to 3 px (edge and operator), inside the
    # margins and away from clipped pixels.
    usable = np.zeros((height, width), bool)
    usable[MARGIN:-MARGIN, MARGIN:-MARGIN] = True
    clipped = ((image == 0) | (image == 255)).any(axis=2).astype(np.uint8)
    usable &= cv2.dilate(clipped, np.ones((2 * MARGIN + 1, 2 * MARGIN + 1), np.uint8)) == 0
    usable &= magnitude * np.sqrt(2.0 * np.pi) * 3.0 >= MIN_CONTRAST
    rows, cols = np.nonzero(usable)
    sharp = magnitude[rows, cols]
    # Non-maximum suppression: the magnitude one pixel ahead and behind across the edge (bilinear).
    points = np.stack([rows, cols], axis=1).astype(np.float32)
    normal = np.stack([gy[rows, cols], gx[rows, cols]], axis=1) / sharp[:, None]
    ahead, behind = (ndimage.map_coordinates(magnitude, (points + shift * normal).T, order=1, mode="nearest")
                     for shift in (1.0, -1.0))
    maxima = (sharp >= ahead) & (sharp > behind)
    sharp, blurred = sharp[maxima], reblurred[rows[maxima], cols[maxima]]
    ratio_squared = (sharp / np.maximum(blurred, 1e-6)) ** 2
    measurable = ratio_squared > 1.0 + 1e-6
    spread_squared = REBLUR_SIGMA**2 / (ratio_squared[measurable] - 1.0)  # edge + operator, px²
    contrast = sharp[measurable] * np.sqrt(2.0 * np.pi * spread_squared)
    variance = (spread_squared - GRADIENT_VARIANCE)[contrast >= MIN_CONTRAST]
    if variance.size == 0:
        return BlurEstimate(0.0, 0)
    return BlurEstimate(float(np.sqrt(max(float(np.median(variance)), 0.0))), int(variance.size))
