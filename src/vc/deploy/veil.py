"""A frame veiled beyond the bundle's range, its contrast stretched back before the networks (numpy only).

Thick fog, a dome's glare, a lens fogged from inside or a camera's own low-contrast setting leave the view where it
was and take its contrast: COCO-C's contrast at severities 4 and 5 keeps a tenth and a twentieth of it. The scene
fitness reads such a PETS09 frame ``dark`` (the scene's light under the veil, -3.4 stops, past the range's -3.2) or
``covered`` (its coarse luminance varies 0.05 of the background's, under :data:`~vc.deploy.fitness.COVERED_SPREAD`),
and its people are withheld, where YOLO11n-pose @1280 still reads them (AP50 0.93 and 0.67). Yet the frame's
structure still correlates 0.9 with the background's: the view is there, faint. Such a frame is mapped, channel by
channel, back onto the background's tone by the line that takes the frame's light to the background's, fitted on the
median of each band of the background's luminance (the bands the fitness fits its veil on: people are a minority of
each), and judged again; the runtime runs the networks on it when it is then fit and matches the background on at
least :data:`~vc.deploy.exposure.BROUGHT_BACK_AGREEMENT` of its cells, as a frame brought back from light beyond the
range is (:mod:`vc.deploy.exposure`).

The line is fitted in two spaces and the one that fits the bands better is taken: in 8-bit codes (a camera's or an
encoder's contrast, COCO-C's: restored, a PETS09 frame matches the background on 0.96-0.97 of its cells, 0.78 by the
other) and in linear light through the camera's response (a veil of airlight, Koschmieder's ``t L + (1 - t) A``:
0.95-0.98, 0.81-0.86 by the other). A frame is stretched by at most :data:`MAX_STRETCH`: one that kept less of the
background's contrast has too few codes left to be read (its bands are steps of the stretch) and stays as judged.
What a covered frame is does not change: black, uniform and noise frames have no view to stretch (no spread, or no
coherence and no structure of the background's), and yield no one. Only frames that would otherwise be withheld pay
for it (a fit, a table lookup and a second fitness: a PETS09 frame stretched back and run takes 1.45x one withheld),
as for exposure (docs/decisions/0021-veil-taken-off.md).
"""

from __future__ import annotations

import numpy as np

from vc.deploy.fitness import (
    COVERED,
    COVERED_COHERENCE,
    DARK,
    KEPT_VIEW_CORRELATION,
    MIN_CELLS,
    OVEREXPOSED,
    VEIL_SHARE,
    FrameFitness,
    SceneReference,
    cell_means,
    clipped_cells,
    fitted_line,
)

#: At most this stretch of the frame's contrast: 1/20 of it (COCO-C's contrast 5) is read back, matching the background
#: on 0.96 of PETS09's cells; a frame stretched further shows its 8-bit steps as bands.
MAX_STRETCH = 25.0
#: The runtime keeps the last frame's tables while this frame's differ from them by at most this many codes: it starts
#: the networks on a frame before its fitness is known (:class:`vc.deploy.runtime.Runtime`), and this is about what a
#: quarter stop, the bound kept for exposure (:data:`~vc.deploy.exposure.KEPT_CORRECTION_STOPS`), moves mid-grey.
KEPT_TABLE_CODES = 8


def veiled(fitness: FrameFitness) -> bool:
    """Whether ``fitness`` reads a frame that may be a view under a veil beyond the range: ``dark`` or
    ``overexposed`` under a veil of more of the light than a real frame's fit reads (:data:`~vc.deploy.fitness.
    VEIL_SHARE`; without one, the light alone is off, which :mod:`vc.deploy.exposure` brings back within its reach),
    or ``covered`` by a faint contrast over a coherent view with the background's structure."""
    if fitness.state in (DARK, OVEREXPOSED):
        return (fitness.veil or 0.0) > VEIL_SHARE
    return fitness.state == COVERED and (fitness.spread or 0.0) * MAX_STRETCH >= 1.0 \
        and (fitness.coherence or 0.0) >= COVERED_COHERENCE and (fitness.correlation or 0.0) >= KEPT_VIEW_CORRELATION


def veil_tables(reference: SceneReference, frame: np.ndarray) -> np.ndarray | None:
    """(3, 256) uint8: per channel, the table that maps ``frame``'s codes onto the background's tone (module
    docstring); None when a band fit is impossible (too few unclipped bands) or would stretch the frame's codes by
    more than :data:`MAX_STRETCH` or flip its tone."""
    derived = reference.derived
    cells = cell_means(frame, reference.cell_px)
    unclipped = ~(derived["clipped"] | clipped_cells(cells))
    kept = [band & unclipped for band in derived["bands"]]
    usable = [index for index, band in enumerate(kept) if np.count_nonzero(band) >= MIN_CELLS]
    if len(usable) < 3:
        return None
    decode = reference.decode.astype(np.float64)
    codes = np.arange(256, dtype=np.float64)
    tables = np.empty((3, 256), np.uint8)
    for channel in range(3):
        background = np.array([float(np.median(reference.cells[..., channel][kept[index]])) for index in usable])
        seen = np.array([float(np.median(cells[..., channel][kept[index]])) for index in usable])
        code_gain, code_offset = fitted_line(background, seen)
        if code_gain < 1.0 / MAX_STRETCH:  # too little contrast left to read, or the tone flipped
            return None
        background_light, seen_light = np.interp(background, codes, decode), np.interp(seen, codes, decode)
        light_gain, light_offset = fitted_line(background_light, seen_light)
        code_error = float(np.sum((code_gain * background + code_offset - seen) ** 2))
        predicted = np.interp(light_gain * background_light + light_offset, decode, codes)
        light_error = float(np.sum((predicted - seen) ** 2))
        if code_error <= light_error or light_gain <= 0:
            restored = (codes - code_offset) / code_gain
        else:
            restored = np.interp((decode - light_offset) / light_gain, decode, codes)
        tables[channel] = np.clip(np.rint(restored), 0, 255).astype(np.uint8)
    return tables


def near(tables: np.ndarray, others: np.ndarray) -> bool:
    """Whether two sets of tables differ by at most :data:`KEPT_TABLE_CODES` anywhere."""
    return int(np.max(np.abs(tables.astype(np.int16) - others.astype(np.int16)))) <= KEPT_TABLE_CODES


def unveiled(frame: np.ndarray, tables: np.ndarray) -> np.ndarray:
    """``frame`` ((H, W, 3) uint8 RGB) through ``tables`` ((3, 256) uint8), channel by channel."""
    return np.stack([np.take(tables[channel], frame[..., channel]) for channel in range(3)], axis=-1)  # 1.7 ms, PETS09
