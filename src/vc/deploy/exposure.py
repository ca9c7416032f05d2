"""A frame lit beyond the bundle's range, brought back to it before the networks (numpy only).

A bundle's networks are compiled over the camera's exposure range (docs/decisions/0014-camera-range.md); a frame the
scene fitness reads ``dark`` or ``overexposed`` lies beyond it, and its people would be withheld. Sun on snow, a
dome's glare or COCO-C's brightness lift PETS09 by +1.4 to +1.7 stops, past the range's +1, while the view itself
is still there. Such a frame, up to :data:`REACH_STOPS` beyond the range's bound, is scaled in linear light through
the camera's response to the background's exposure and judged again: the runtime runs the networks on the frame
brought back when it is then fit and matches the background on at least :data:`BROUGHT_BACK_AGREEMENT` of its
cells, as a frame of the background's own look does. Exposure is all this corrects: a frame that was also changed
otherwise (COCO-C's snow lifts PETS09 +1.4 stops and, brought back, matches on 0.44-0.47 of its cells, where its
networks invent a dozen people) stays withheld. Only frames that would otherwise be withheld pay for it, a table
lookup over the frame and a second fitness (a PETS09 frame brought back and run takes 1.7x one withheld): the frames
within the range go to the networks as the camera gave them, since dividing their tone out buys too little for its
time there (docs/decisions/0015-tone-normalisation.md). Clipped light stays clipped: a frame's white becomes the
grey it would be under the gain; beyond the reach too much of the view is clipped or lost in the dark to bring back
(docs/decisions/0018-exposure-brought-back.md).
"""

from __future__ import annotations

import numpy as np

from vc.deploy.fitness import CHANGED_AGREEMENT

#: How far beyond the fit range's exposure bound a frame is still brought back, in stops.
REACH_STOPS = 1.0
#: A frame brought back is run when at least this share of its cells then match the background: the background's
#: own look's bound, not a range's widened one (module docstring). PETS09 under COCO-C's brightness reads 0.71-0.76
#: brought back, under its snow 0.44-0.47.
BROUGHT_BACK_AGREEMENT = CHANGED_AGREEMENT
#: The runtime keeps the last frame's correction while the frame's own is within this many stops of it
#: (:class:`vc.deploy.runtime.Runtime`): it starts the networks on a frame before its fitness is known, and a
#: quarter stop is far within what the networks were compiled to hold.
KEPT_CORRECTION_STOPS = 0.25


def exposure_table(decode: np.ndarray, stops: float) -> np.ndarray:
    """The (256,) uint8 table that changes a frame's exposure by ``stops`` through the camera response ``decode``
    ((256,) linear light per code, rising): each code's light scaled by ``2 ** stops`` and encoded to the nearest
    code of the same response (clipped to 0-255)."""
    decode = np.asarray(decode, np.float64)
    codes = np.arange(256, dtype=np.float64)
    scaled = decode * 2.0 ** float(stops)
    return np.clip(np.rint(np.interp(scaled, decode, codes)), 0, 255).astype(np.uint8)


def correction_stops(exposure_stops: float, dark_stops: float, overexposed_stops: float) -> float | None:
    """The stops that bring a frame of ``exposure_stops`` (against the background, as the fitness reads it) to the
    background's exposure, when it lies beyond a range that holds ``-dark_stops`` to ``overexposed_stops`` by at
    most :data:`REACH_STOPS`; None when it is within the range or beyond the reach."""
    beyond = max(exposure_stops - overexposed_stops, -dark_stops - exposure_stops)
    return -exposure_stops if 0.0 < beyond <= REACH_STOPS else None


def exposed(frame: np.ndarray, decode: np.ndarray, stops: float) -> np.ndarray:
    """``frame`` ((H, W, 3) uint8 RGB) with its exposure changed by ``stops`` (:func:`exposure_table`)."""
    return np.take(exposure_table(decode, stops), frame)  # take: half the time of indexing (1.3 ms on PETS09)
