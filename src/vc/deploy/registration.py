"""Where a camera's view lies now against its background: a move of whole pixels and a roll about the lens's axis,
read on the scene fitness's coarse cells and undone on the frame before the networks (numpy only).

A bracket that settles or a camera knocked moves its view and may turn it. The fully convolutional networks meet a
move as another position of their windows once the region map moves with the view; a turn they do not meet: their
renders show the background upright, and a PETS09 bundle whose camera rolled 1 degree reports people on the empty
background (docs/decisions/0026-camera-roll.md). So the runtime reads both and undoes them
(:meth:`vc.deploy.fitness.SceneReference.register`):

1. **The move**: the phase correlation of the frame's coarse luminance with the background's
   (:func:`phase_correlation`: Hann window, the peak refined by a parabola per axis).
2. **The roll**: the same correlation on the left and right halves of the cells, and on the top and bottom halves
   (:class:`HalvesReference`). A view turned by ``a`` (counter-clockwise on the screen) lifts its right half and
   lowers its left by ``a`` times the halves' distance, and moves its top half left and its bottom half right; the
   two readings are weighed by their lever arms, each only where both its halves' correlation peaks are clear.
   Coarse cells read a small turn short (1 degree as 0.4-0.6), so the view is turned back by what they read and
   read again, as the move's rounds do.
3. **The view undone**: one gather of the frame's pixels per frame (:func:`view_back`), the nearest pixel (half a
   pixel at most off, under what the networks' input scales resolve), its indices kept for the registration in
   force. A view that only moved is cut and padded (:func:`translated`), as before a roll was read.

A person found on the view undone is put back where the camera shows them by :meth:`Registration.forward`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Registration:
    """How the view moved from the background's: its content turned by ``roll_deg`` (counter-clockwise on the screen)
    about the frame's centre, then moved by (``dx``, ``dy``) whole pixels. The view undone shows at pixel ``p`` what
    the frame shows at :meth:`forward` ``(p)``."""

    dx: int = 0
    dy: int = 0
    roll_deg: float = 0.0

    @property
    def still(self) -> bool:
        return self.dx == 0 and self.dy == 0 and self.roll_deg == 0.0

    @property
    def shift(self) -> tuple[int, int]:
        return self.dx, self.dy

    def matrix(self, frame_size: tuple[int, int]) -> np.ndarray:
        """The (2, 3) map from the background's pixels to the frame's (``frame_size``: width, height), pixel centres
        at whole coordinates."""
        width, height = frame_size
        centre_x, centre_y = (width - 1) / 2.0, (height - 1) / 2.0
        angle = math.radians(self.roll_deg)
        cosine, sine = math.cos(angle), math.sin(angle)
        return np.array([[cosine, sine, centre_x - cosine * centre_x - sine * centre_y + self.dx],
                         [-sine, cosine, centre_y + sine * centre_x - cosine * centre_y + self.dy]])

    def forward(self, points: np.ndarray, frame_size: tuple[int, int]) -> np.ndarray:
        """``points`` (N, 2) x, y found on the view undone, where the frame shows them."""
        matrix = self.matrix(frame_size)
        return np.asarray(points, np.float64).reshape(-1, 2) @ matrix[:, :2].T + matrix[:, 2]


def translated(frame: np.ndarray, shift: tuple[int, int]) -> np.ndarray:
    """``frame`` with its content moved back by ``shift`` (x, y) whole pixels: ``result[y, x] = frame[y + dy, x +
    dx]``, the edge's pixels repeated where the frame has none (what a view moved by ``shift`` showed where the
    background has it)."""
    dx, dy = int(shift[0]), int(shift[1])
    if dx == 0 and dy == 0:
        return frame
    height, width = frame.shape[:2]
    if abs(dx) >= width or abs(dy) >= height:
        raise ValueError(f"a shift of {shift} leaves nothing of a {width}x{height} frame")
    kept = frame[max(dy, 0):height + min(dy, 0), max(dx, 0):width + min(dx, 0)]
    return np.pad(kept, ((max(-dy, 0), max(dy, 0)), (max(-dx, 0), max(dx, 0)), (0, 0)), mode="edge")


def view_back(frame: np.ndarray, registration: Registration) -> np.ndarray:
    """``frame`` (H, W, C) as the background's view: its move and roll undone, the nearest pixel, the edge's pixels
    repeated where the frame has none."""
    if registration.roll_deg == 0.0:
        return translated(frame, registration.shift)
    height, width = frame.shape[:2]
    flat = _gather_indices(height, width, registration)
    return np.take(frame.reshape(height * width, -1), flat, axis=0).reshape(frame.shape)  # 4x fancy indexing's speed


@functools.lru_cache(maxsize=4)
def _gather_indices(height: int, width: int, registration: Registration) -> np.ndarray:
    """The flat index of the frame's pixel each pixel of the view undone takes (kept: a registration holds for many
    frames)."""
    rows, columns = np.indices((height, width), dtype=np.float64)
    matrix = registration.matrix((width, height))
    x = matrix[0, 0] * columns + matrix[0, 1] * rows + matrix[0, 2]
    y = matrix[1, 0] * columns + matrix[1, 1] * rows + matrix[1, 2]
    x = np.clip(np.rint(x), 0, width - 1).astype(np.int64)
    y = np.clip(np.rint(y), 0, height - 1).astype(np.int64)
    return (y * width + x).ravel()


def hann_window(shape: tuple[int, int]) -> np.ndarray:
    return np.outer(np.hanning(shape[0]), np.hanning(shape[1])).astype(np.float32)


def spectrum(luma: np.ndarray, window: np.ndarray) -> np.ndarray:
    """The conjugate spectrum of a reference's windowed luminance, what :func:`phase_correlation` compares with."""
    return np.conj(np.fft.rfft2((luma - luma.mean()) * window))


def phase_correlation(luma: np.ndarray, window: np.ndarray, conjugate: np.ndarray) -> tuple[float, float, float]:
    """(x, y, peak): how far, in cells, ``luma``'s content moved from the reference whose :func:`spectrum` is
    ``conjugate``, and the correlation's peak (1: the same picture; floored at 0)."""
    cross = np.fft.rfft2((luma - luma.mean()) * window) * conjugate
    cross /= np.abs(cross) + 1e-9
    surface = np.fft.irfft2(cross, s=luma.shape)
    row, column = np.unravel_index(int(np.argmax(surface)), surface.shape)
    height, width = surface.shape
    peak = float(surface[row, column])
    y = row + _parabola_offset(surface[(row - 1) % height, column], peak, surface[(row + 1) % height, column])
    x = column + _parabola_offset(surface[row, (column - 1) % width], peak, surface[row, (column + 1) % width])
    y, x = (y - height if y > height / 2 else y), (x - width if x > width / 2 else x)  # wrapped: negative shifts
    return float(x), float(y), max(peak, 0.0)


def _parabola_offset(before: float, peak: float, after: float) -> float:
    curvature = before - 2.0 * peak + after
    return 0.0 if curvature >= 0 else float(np.clip(0.5 * (before - after) / curvature, -0.5, 0.5))


class HalvesReference:
    """The background's coarse luminance (h, w) cut in halves, left and right, top and bottom, each ready for
    :func:`phase_correlation`: a frame's :meth:`roll` is read from how its halves moved (module docstring)."""

    def __init__(self, luma: np.ndarray) -> None:
        height, width = luma.shape
        self.width, self.height = width, height
        self.halves = [(part, hann_window(luma[part].shape), spectrum(luma[part], hann_window(luma[part].shape)))
                       for part in ((slice(None), slice(0, width // 2)), (slice(None), slice(width // 2, None)),
                                    (slice(0, height // 2), slice(None)), (slice(height // 2, None), slice(None)))]

    def roll(self, luma: np.ndarray, clear_peak: float) -> float:
        """How far ``luma``'s content turned from the background's, degrees counter-clockwise on the screen, as the
        cells read it (short for a small turn). A pair of halves counts only when both their correlation peaks reach
        ``clear_peak``: a half that a crowd or a corruption leaves without a clear peak moves anywhere (TUD-Stadtmitte
        read turns of 5-7 degrees so); with neither pair clear, the reading is 0."""
        (_, left_y, left), (_, right_y, right), (top_x, _, top), (bottom_x, _, bottom) = [
            phase_correlation(luma[part], window, conjugate) for part, window, conjugate in self.halves]
        pairs = [(-(right_y - left_y) / (self.width / 2.0), self.width ** 2, min(left, right)),  # radians, lever arm
                 ((bottom_x - top_x) / (self.height / 2.0), self.height ** 2, min(top, bottom))]
        clear = [(reading, arm) for reading, arm, peak in pairs if peak >= clear_peak]
        if not clear:
            return 0.0
        return math.degrees(sum(reading * arm for reading, arm in clear) / sum(arm for _, arm in clear))
