"""Camera response: between the 8-bit values a camera writes and linear light.

Rendering and compositing happen in linear light (docs/design.md, "Conventions"); the background photograph is
decoded with the scene's response and the composite encoded back with the same one. Responses accepted by the
scene schema: ``srgb`` (IEC 61966-2-1, through colour-science), ``linear``, and a pure power law ``gamma G``.
This is the seam for photometric calibration: a fitted curve would be one more response here.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import colour
import numpy as np

#: Linear values are quantised to this many steps before encoding through a table: 16 bits keep the sRGB
#: curve's steep start within 0.05 of an 8-bit step, at a fraction of evaluating the curve per pixel.
ENCODE_STEPS = 65535


def _without_nan(values: np.ndarray, action: str, dtype: type = np.float64) -> np.ndarray:
    """``values`` as ``dtype``; NaN (a value that is no light at all) is an error, +-inf clips like any overflow."""
    with np.errstate(over="ignore"):  # beyond float32's range is +-inf, which clips like any overflow
        array = np.asarray(values, dtype)
    if np.isnan(array).any():
        raise ValueError(f"{int(np.isnan(array).sum())} of {array.size} values are NaN and cannot be {action}")
    return array


@dataclass(frozen=True)
class Response:
    """A camera response named as in the scene schema."""

    name: str

    @property
    def gamma(self) -> float | None:
        return float(self.name.split()[1]) if self.name.startswith("gamma") else None

    def _curve_decode(self, values: np.ndarray) -> np.ndarray:
        if self.name == "srgb":
            return np.asarray(colour.cctf_decoding(values, function="sRGB"))
        if self.name == "linear":
            return values
        return np.power(np.clip(values, 0.0, None), self.gamma)

    def _curve_encode(self, values: np.ndarray) -> np.ndarray:
        if self.name == "srgb":
            return np.asarray(colour.cctf_encoding(values, function="sRGB"))
        if self.name == "linear":
            return values
        return np.power(values, 1.0 / self.gamma)

    @functools.cached_property
    def _decode_table(self) -> np.ndarray:
        return self._curve_decode(np.arange(256) / 255.0).astype(np.float32)

    @functools.cached_property
    def _encode_table(self) -> np.ndarray:
        return np.round(self._curve_encode(np.arange(ENCODE_STEPS + 1) / ENCODE_STEPS) * 255.0).astype(np.uint8)

    def decode(self, image: np.ndarray) -> np.ndarray:
        """uint8 (or [0, 1] float) image -> linear float32. Values outside [0, 1] stay finite (the curves are
        extended, a power law clipped at 0); NaN is refused rather than passed on."""
        if image.dtype == np.uint8:
            return self._decode_table[image]
        values = _without_nan(image, "decoded")
        return self._curve_decode(values).astype(np.float32)

    def encode_exact(self, linear: np.ndarray) -> np.ndarray:
        """Linear image -> uint8 through the curve itself (no table): for one-off images such as a rendered
        background, where exactness is worth more than the 5x speed of :meth:`encode`."""
        values = np.clip(_without_nan(linear, "encoded"), 0.0, 1.0)
        return np.round(self._curve_encode(values) * 255.0).astype(np.uint8)

    def encode(self, linear: np.ndarray) -> np.ndarray:
        """Linear image -> uint8, clipped to the sensor's range as a camera does: through a table (within one
        8-bit level of :meth:`encode_exact`) for sRGB and linear; a pure power law starts too steeply for a 16-bit
        table (gamma 2.6 puts level 2 at linear 3e-6, below its first step), so it goes through the curve."""
        if self.gamma is not None:
            return self.encode_exact(linear)
        steps = np.clip(_without_nan(linear, "encoded", np.float32), 0.0, 1.0) * np.float32(ENCODE_STEPS) \
            + np.float32(0.5)
        return self._encode_table[steps.astype(np.int32)]
