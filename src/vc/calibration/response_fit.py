"""``response: auto``: the camera's response curve fitted from the one background image, where the image shows it.

Method: colour edges (Lin, Gu, Yamazaki & Shum, "Radiometric calibration from a single image", CVPR 2004). A pixel
on an edge between two uniformly coloured areas sees some of each: in linear light its colour is a mixture
``a A + (1 - a) B``, on the segment between the two sides' colours. A non-linear response bends the segment, so
in the values the camera wrote the edge pixels fall off it. Decoding the image through each candidate response
and measuring how far the edge pixels lie from their segments (relative to the segment's length), the right
response is the one that straightens them.

Candidates: power laws ``gamma 1.0`` (linear) to ``gamma 3.0`` in steps of 0.1, and sRGB. Lin et al. fit a
PCA model of measured curves (DoRF); a one-parameter family is what the scene schema can name and what the
renderer encodes with, and it is enough to tell linear, sRGB and the gammas cameras use apart.

The fit is only as good as its edges, and the image says when it is not: edges between two colours of the same
chromaticity stay straight under every response (they are not used), and chroma subsampling (4:2:0 video,
most JPEG) blurs colour over twice the width of luma, so edge pixels are no longer mixtures of one blur. When
the best candidate does not stand out (its misfit is not well below the typical candidate's) or there are too
few edges, the fit says the response is not identifiable from this image and the scene gets sRGB, the
broadcast default (IEC 61966-2-1), with that reason in the plan. A sequence with known exposure changes
(Debevec & Malik 1997) would identify it; a single surveillance image does not have one.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from vc.calibration.response import Response
from vc.io import read_image

#: The responses the fit chooses from, by the names the scene schema uses.
CANDIDATES = ("linear", *(f"gamma {g / 10:.1f}" for g in range(11, 31)), "srgb")
#: The response a scene gets when the image does not identify one.
FALLBACK = "srgb"
#: Each side of an edge is read this many pixels from the edge pixel, across the edge, as the mean of a 3 x 3
#: patch: past the half-width of a camera's edge blur (about 1-2 px), inside the area either side.
SIDE_OFFSET = 3
#: A side is uniform when its 3 x 3 patch varies less than this (standard deviation, [0, 1] values, per channel).
MAX_SIDE_SPREAD = 0.02
#: The two sides differ by at least this much (Euclidean, [0, 1] RGB): a weak edge's mixture is lost in noise.
MIN_SIDE_DISTANCE = 0.15
#: ... and in chromaticity by at least this angle (degrees) between their RGB vectors: two colours of one
#: chromaticity span a segment through the grey axis's direction, which every response keeps straight.
MIN_CHROMA_ANGLE_DEG = 5.0
#: The edge pixel is a mixture, not one of the sides: its position along the segment, in 8-bit values, is in here.
MIXTURE_RANGE = (0.2, 0.8)
#: Edge pixels used at most (the strongest, in raster order among equals: deterministic).
MAX_EDGES = 20000
#: Fewer usable edge pixels than this and the fit does not choose.
MIN_EDGES = 200
#: The best candidate is chosen when its misfit is at most this share of the median candidate's. On images the
#: project renders through known curves the right one scores 0.2-0.5 of the median; on a 4:2:0 Xvid frame
#: (PETS09) every candidate scores within a few per cent of the others.
MAX_RELATIVE_MISFIT = 0.7


@dataclass(frozen=True)
class ResponseFit:
    """The response chosen for a scene (``name``), whether the image identified it, and the evidence."""

    name: str
    identified: bool
    reason: str
    edges: int = 0
    misfits: dict[str, float] = field(default_factory=dict)  # candidate -> median relative off-segment distance

    @property
    def response(self) -> Response:
        return Response(self.name)

    def to_dict(self) -> dict:
        return {"name": self.name, "identified": self.identified, "reason": self.reason, "edges": self.edges,
                "misfits": {name: round(value, 5) for name, value in self.misfits.items()}}


def _edge_triples(image: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixel positions of usable edge pixels and of their two sides: (centre, side A, side B) as (N, 2) rows,
    columns. Chosen in the camera's own values: where gradients are strong and both sides are uniform."""
    values = image.astype(np.float32) / 255.0
    height, width = values.shape[:2]
    gray = values.mean(axis=2)
    gx = cv2.Sobel(gray, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(gray, cv2.CV_32F, 0, 1, ksize=3)
    magnitude = np.hypot(gx, gy)
    margin = SIDE_OFFSET + 2
    magnitude[:margin], magnitude[-margin:], magnitude[:, :margin], magnitude[:, -margin:] = 0, 0, 0, 0
    # Across-edge direction, quantised to the 8 neighbours so that the sides are whole pixels.
    angle = np.arctan2(gy, gx)
    step_y = np.rint(np.sin(angle) * np.sqrt(2)).clip(-1, 1).astype(np.int64)
    step_x = np.rint(np.cos(angle) * np.sqrt(2)).clip(-1, 1).astype(np.int64)
    mean = cv2.blur(values, (3, 3))
    spread = np.sqrt(np.maximum(cv2.blur(values * values, (3, 3)) - mean * mean, 0.0)).max(axis=2)
    strong = np.flatnonzero(magnitude.ravel() > 0.1)
    order = strong[np.argsort(-magnitude.ravel()[strong], kind="stable")]
    rows, cols = np.unravel_index(order, (height, width))
    dy, dx = step_y[rows, cols] * SIDE_OFFSET, step_x[rows, cols] * SIDE_OFFSET
    a_rows, a_cols, b_rows, b_cols = rows - dy, cols - dx, rows + dy, cols + dx
    uniform = (spread[a_rows, a_cols] < MAX_SIDE_SPREAD) & (spread[b_rows, b_cols] < MAX_SIDE_SPREAD)
    side_a, side_b, centre = mean[a_rows, a_cols], mean[b_rows, b_cols], values[rows, cols]
    difference = side_b - side_a
    length = np.linalg.norm(difference, axis=1)
    norms = np.linalg.norm(side_a, axis=1) * np.linalg.norm(side_b, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        sine = np.linalg.norm(np.cross(side_a, side_b), axis=1) / norms
        position = np.einsum("ij,ij->i", centre - side_a, difference) / length**2
    chromatic = np.nan_to_num(sine) > np.sin(np.radians(MIN_CHROMA_ANGLE_DEG))
    between = (position > MIXTURE_RANGE[0]) & (position < MIXTURE_RANGE[1])
    keep = np.flatnonzero(uniform & (length > MIN_SIDE_DISTANCE) & chromatic & between)[:MAX_EDGES]
    return (np.stack([rows[keep], cols[keep]], 1), np.stack([a_rows[keep], a_cols[keep]], 1),
            np.stack([b_rows[keep], b_cols[keep]], 1))


def _misfit(linear: np.ndarray, centre: np.ndarray, side_a: np.ndarray, side_b: np.ndarray) -> float:
    """Median distance of the edge pixels from the segment between their sides, in units of its length."""
    mean = cv2.blur(linear, (3, 3))
    a, b = mean[side_a[:, 0], side_a[:, 1]], mean[side_b[:, 0], side_b[:, 1]]
    m = linear[centre[:, 0], centre[:, 1]]
    difference = b - a
    length_squared = np.maximum(np.einsum("ij,ij->i", difference, difference), 1e-12)
    position = np.clip(np.einsum("ij,ij->i", m - a, difference) / length_squared, 0.0, 1.0)
    off = np.linalg.norm(m - (a + position[:, None] * difference), axis=1)
    return float(np.median(off / np.sqrt(length_squared)))


def fit_response(image: np.ndarray) -> ResponseFit:
    """The response of the camera that wrote ``image`` (RGB uint8), or :data:`FALLBACK` when the image does not
    identify one (see the module docstring)."""
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {image.dtype} {image.shape}")
    centre, side_a, side_b = _edge_triples(image)
    edges = len(centre)
    if edges < MIN_EDGES:
        return ResponseFit(FALLBACK, False, f"{edges} usable colour edges (a fit needs {MIN_EDGES}): {FALLBACK} "
                                            "assumed", edges)
    misfits = {name: _misfit(Response(name).decode(image), centre, side_a, side_b) for name in CANDIDATES}
    best = min(misfits, key=misfits.__getitem__)
    typical = float(np.median(list(misfits.values())))
    ratio = misfits[best] / typical if typical > 0 else 1.0
    if ratio > MAX_RELATIVE_MISFIT:
        return ResponseFit(FALLBACK, False, f"no candidate straightens the colour edges (best, {best}, misfits "
                                            f"{ratio:.2f} of the median candidate's; chroma subsampling and textured "
                                            "edges do this): "
                                            f"{FALLBACK} assumed", edges, misfits)
    return ResponseFit(best, True, f"fitted on {edges} colour edges (misfit {ratio:.2f} of the median candidate's)",
                       edges, misfits)


@functools.lru_cache(maxsize=8)
def _fitted(image_path: Path) -> ResponseFit:
    return fit_response(read_image(image_path))


def resolve_response(name: str, image_path: Path) -> ResponseFit:
    """The scene's response: the one it names, or (``auto``) the one fitted on its background image (once per
    image and process)."""
    if name == "auto":
        return _fitted(Path(image_path))
    return ResponseFit(name, True, "given by the scene")
