"""Prototype (frozen): does normalising a frame's tone against the bundle's background help the networks?

Runs benchmarks.robustness with Runtime.run wrapped: each frame is first mapped, channel by channel, through a
curve fitted on the cells that match the background (options below), then run as shipped.
"""

from __future__ import annotations

import os
import sys

import numpy as np

import vc.deploy.runtime as runtime_module
from vc.deploy.fitness import _clipped as clipped
from vc.deploy.fitness import cell_means

MODEL = os.environ.get("TONE_MODEL", "none")
SELECT_RATIO = float(os.environ.get("SELECT_RATIO", "0.6"))


def robust_affine(x: np.ndarray, y: np.ndarray, with_offset: bool) -> tuple[float, float]:
    """y ~ g x + a, Tukey-weighted least squares."""
    gain = float(np.median(y) / max(np.median(x), 1e-6))
    offset = 0.0
    if with_offset:
        q = np.quantile(x, [0.25, 0.75]), np.quantile(y, [0.25, 0.75])
        gain = float((q[1][1] - q[1][0]) / max(q[0][1] - q[0][0], 1e-6))
        offset = float(np.median(y - gain * x))
    for _ in range(6):
        residual = y - gain * x - offset
        scale = 1.4826 * float(np.median(np.abs(residual))) + 1e-6
        u = residual / (4.685 * scale)
        w = np.where(np.abs(u) < 1, (1 - u ** 2) ** 2, 0.0)
        if with_offset:
            sw = w.sum()
            mx, my = (w * x).sum() / sw, (w * y).sum() / sw
            var = (w * (x - mx) ** 2).sum()
            gain = float((w * (x - mx) * (y - my)).sum() / max(var, 1e-12))
            offset = my - gain * mx
        else:
            gain = float((w * x * y).sum() / max((w * x * x).sum(), 1e-12))
    return gain, offset


def residual_scale(lut: np.ndarray, cells: np.ndarray, background: np.ndarray, usable: np.ndarray) -> float:
    """Robust spread of the background's codes minus the frame's mapped through the lut, on the usable cells."""
    codes = np.arange(256, dtype=np.float64)
    mapped = np.stack([np.interp(cells[..., c], codes, lut[c].astype(np.float64)) for c in range(3)], axis=-1)
    return float(np.median(np.abs(mapped - background)[usable]))


def tone_lut(frame: np.ndarray, reference) -> np.ndarray:
    global MODEL
    if MODEL == "select":
        cells = cell_means(frame, reference.cell_px)
        usable = ~(clipped(cells) | clipped(reference.cells)) & (reference.cells.min(axis=2) > 8)
        try:
            MODEL = "gain-lin"
            gain = tone_lut(frame, reference)
            MODEL = "affine-code"
            affine = tone_lut(frame, reference)
        finally:
            MODEL = "select"
        ratio = residual_scale(affine, cells, reference.cells, usable) / max(
            residual_scale(gain, cells, reference.cells, usable), 1e-6)
        return affine if ratio < SELECT_RATIO else gain
    cells = cell_means(frame, reference.cell_px)
    background = reference.cells
    usable = ~(clipped(cells) | clipped(background)) & (background.min(axis=2) > 8)
    table = reference.decode.astype(np.float64)
    codes = np.arange(256, dtype=np.float64)
    lut = np.empty((3, 256), np.uint8)
    linear = MODEL.endswith("-lin")
    for channel in range(3):
        f, b = cells[..., channel][usable], background[..., channel][usable]
        if linear:
            f, b = np.interp(f, codes, table), np.interp(b, codes, table)
        gain, offset = robust_affine(b, f, with_offset=MODEL.startswith("affine"))
        gain = max(gain, 1e-3)
        source = table if linear else codes
        restored = (source - offset) / gain
        out = np.interp(restored, table, codes) if linear else restored
        lut[channel] = np.clip(np.rint(out), 0, 255).astype(np.uint8)
    return lut


original_run = runtime_module.Runtime.run


def normalised_run(self, frame):
    reference = self.bundle.reference
    if MODEL != "none" and reference is not None:
        lut = tone_lut(frame, reference)
        frame = np.stack([lut[c][frame[..., c]] for c in range(3)], axis=-1)
    return original_run(self, frame)


runtime_module.Runtime.run = normalised_run

if __name__ == "__main__":
    from benchmarks import robustness

    sys.argv[0] = "robustness"
    robustness.main()
