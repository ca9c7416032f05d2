"""Scene fitness: does a frame still show the scene its bundle was compiled for? (numpy only)

A bundle is accurate on frames that look like its background image, and a camera in service does not keep looking
like one image: dusk, white balance, night mode, a dirty lens, a nudged bracket, a lost signal. Each of these made
a bundle invent people (issue 62). The runtime measures every frame against a small reference of the scene's
background that the bundle carries (:class:`SceneReference`) and gives a :class:`FrameFitness`: a state and the
numbers that decided it. What the runtime then does with the people is its ``unfit`` setting
(:mod:`vc.deploy.runtime`); a ``covered`` frame never yields people.

**The reference.** The background reduced at export to what the measurements need, not the picture: the mean 8-bit
codes of its cells, squares of ``cell_px`` pixels, about :data:`REFERENCE_SHORT_SIDE` across the frame's short side
(PETS09, 768x576: 96x72 cells of 8 px); the camera response's decoding table (code -> linear light), because
exposure is a ratio of light, not of codes; and the background's fine-scale gradient energy, the one measurement
that needs full resolution. Stored as one ``.npz`` (numpy's own archive, read without pickling): the runtime has no
image decoder, and PETS09's reduced background is 85 kB against its PNG's 646. Frames are reduced by the same
function (:func:`cell_means`) that reduced the background, so the background's own fitness is ``ok`` with every
difference zero. Why a reduced background and not statistics alone: every state but ``covered`` compares the frame
with the background cell by cell (the exposure on the cells that still match, the shift by correlation, the
structure and colour of each cell), which needs the cells themselves.

**The states**, decided in this order: the first that holds is the frame's. All but the sharpness are measured on the
cells (about 7 000 numbers): a PETS09 frame costs about 1.8 ms of one core, 2.8 with a veil taken off, and half a
millisecond more to read the view's roll (the 2-core development machine, shared), and the runtime measures it while
the networks run (docs/decisions/0013-scene-fitness.md, 0016-weather-and-gain.md, 0026-camera-roll.md).

1. ``covered`` — the frame shows no scene: black, uniform, a covered lens, a lost signal's noise. Either its coarse
   luminance (code luma of the cells) varies less than :data:`COVERED_SPREAD` of the background's (standard
   deviations: flat), or its variation has no spatial coherence: the correlation of neighbouring cells, ``1 - mean
   squared difference / (2 variance)``, is below :data:`COVERED_COHERENCE`. A scene's cells are correlated (0.87
   and more on PETS09 and TUD-Stadtmitte), noise's are not (0.02 at most).
2. ``dark`` / ``overexposed`` — exposure: per cell, the ratio of the frame's linear luminance to the background's,
   in stops; its median over the cells clipped in neither (a clipped cell understates the ratio); then the median
   again over the cells within :data:`MATCH_STOPS` of that first median — the cells that still match the
   background under one gain. People, and whatever else changed, do not follow the gain, and the median ignores
   them while they cover less than half the cells. Below ``-``:data:`DARK_STOPS` the frame is ``dark``, above
   :data:`OVEREXPOSED_STOPS` ``overexposed``. A veil (fog, haze, a dome's glare) adds light that follows no part of
   the scene (Koschmieder: ``t L + (1 - t) A``): the frame's median light per band of the background's luminance
   (:data:`VEIL_BANDS`), fitted as a line, has its airlight as offset, taken block by block since fog is patchy.
   When taking it off makes :data:`VEIL_AGREEMENT` more of the cells match (step 5), the ratios, the exposure and
   the colour are the scene's light without it, and the frame's ``veil`` is the airlight's share of its light.
3. ``blurred`` — sharpness: the frame's fine-scale gradient energy (mean squared difference of neighbouring pixels,
   green channel, full resolution, per row of cells) over the background's, the median over the rows, divided by
   the square of step 1's spread. Contrast and exposure scale the squared differences as the square of the spread
   and cancel; blur takes the fine energy and leaves the spread of the cells (dividing by the cells' own gradient
   energy instead failed on small frames, whose 4 px cells a blur of 2 px smooths too). Squared differences, not
   absolute ones: blur keeps a monotone edge's total variation and only spreads it. Below
   :data:`BLURRED_SHARPNESS`.
4. ``moved`` — alignment: the global shift of the frame's coarse luminance against the background's by phase
   correlation (numpy FFT, Hann window, the peak refined by a parabola per axis), in frame pixels, and the view's
   roll read from how its halves moved (:mod:`vc.deploy.registration`). Beyond :data:`MOVED_PX` or
   :data:`ROLLED_DEG`, when the correlation peak is clear (at least :data:`MOVED_PEAK`): an unrelated frame's peak is
   anywhere and says nothing. The coarse cells read shifts under a cell short (3 px as 1.5-2.3 on PETS09's 8 px
   cells), and small turns too: the bounds are on what they read. :meth:`SceneReference.register` measures a move to
   the whole pixel (up to :data:`REGISTRATION_BOUND_PX`) and a roll (up to :data:`REGISTRATION_BOUND_DEG`), for the
   runtime to compensate; a frame it has moved back reads ``ok``.
5. ``changed`` — a veil over more than :data:`VEIL_SHARE` of the light; a noise (the frame's fine energy beyond the
   background's at its contrast, per pixel) over :data:`NOISE_CODES`; another view: the structure of the cells' coarse
   luminance (less its own blur: edges and texture, whatever light or veil lies over them) correlates under
   :data:`SAME_VIEW_CORRELATION` with the background's; or agreement: fewer than
   :data:`CHANGED_AGREEMENT` of the cells match the background: their light is within :data:`MATCH_STOPS` of the
   frame's gain (step 2) and, between bright unclipped neighbours, their ratio to the background changes by at most
   :data:`STRUCTURE_STOPS` from cell to cell (the background's structure, whatever the exposure: a flat thing in
   front of textured ground does not match where its light happens to be the ground's), both widened by
   :data:`NOISE_SIGMAS` of the cell's noise (a cell averages a few pixels of it), while the view's structure
   correlates under :data:`KEPT_VIEW_CORRELATION` (a patchy veil's light fails the cells' test where the structure
   shows the whole view still there). The view itself changed, over more of it than a crowd covers. Or its colour
   did, on the matching cells bright enough to have one (:data:`COLOUR_FLOOR`): less than :data:`COLOUR_LEFT` of the
   background's colour variation is left (a monochrome night mode), or a cast of more than :data:`COLOUR_CAST_STOPS`
   (white balance): the median of each cell's log chromaticity (R/G, B/G in linear light) minus the background's,
   scaled by the colour left (a veil or snow takes colour away toward grey without a cast).

The bounds of steps 2, 3 and 5 are the bundle's :class:`FitRange`: the constants below for a bundle compiled for the
background's one look, wider for one compiled over the camera's range (a monochrome frame is then fit too, and a
noisy, veiled, snowy or defocused one as far as the range went: docs/decisions/0016-weather-and-gain.md).
Otherwise ``ok``. A bundle without a reference gives ``unknown``, with the reason. Every number is finite whatever
the frame (black, white, one bright pixel): divisions have floors and empty selections fall back.
"""

from __future__ import annotations

import io
import math
import zipfile
from dataclasses import dataclass, field

import numpy as np

from vc.deploy.registration import (
    HalvesReference,
    Registration,
    hann_window,
    phase_correlation,
    spectrum,
    translated,
    view_back,
)

#: The states a frame can be in; every state but ``ok`` and ``unknown`` is unfit.
OK, DARK, OVEREXPOSED, COVERED, BLURRED, MOVED, CHANGED, UNKNOWN = (
    "ok", "dark", "overexposed", "covered", "blurred", "moved", "changed", "unknown")
STATES = (OK, DARK, OVEREXPOSED, COVERED, BLURRED, MOVED, CHANGED, UNKNOWN)
UNFIT_STATES = (DARK, OVEREXPOSED, COVERED, BLURRED, MOVED, CHANGED)

#: Cells across the frame's short side: a person of PETS09 (50-100 px) spans 6-12 cells of 8 px, so people stay a
#: minority of cells, and 7 000 cells make the medians exact to a fraction of a stop at a millisecond a frame.
REFERENCE_SHORT_SIDE = 72
#: The smallest cell, in pixels: a cell averages at least 16 pixels, so that a lost signal's noise averages out and
#: shows as incoherent (step 1) on small frames too.
MIN_CELL_PX = 4
#: Pixels of a cell averaged per side at most (evenly spaced): PETS09's 8 px cells average 16 of their pixels, at half
#: the cost of all 64 with the same states and numbers within 0.01, and a 4K frame's 30 px cells cost what they do.
MAX_SAMPLES_PER_SIDE = 4
#: Fine energy is measured on every this-many-th row of cells (:func:`fine_energy`): 36 rows of PETS09's 72 are
#: plenty for a median, at half the cost.
FINE_ROW_STEP = 2
#: Rec. 709 luminance weights, for codes (the coarse luma) and for linear light (the exposure).
LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)
#: Linear light added to both sides of a ratio: about sRGB code 3. Darker cells say nothing about the exposure but
#: their noise, and a black cell's ratio stays finite.
LINEAR_FLOOR = 1e-3
#: A cell with a channel at or above this code is clipped: its ratio understates the light.
CLIPPED_CODE = 250

#: Covered: the frame's coarse luminance varies less than this share of the background's. Black and uniform frames
#: read 0, noise 0.29 or more (PETS09); 3 stops less light still reads 0.41.
COVERED_SPREAD = 0.1
#: Covered: neighbouring cells correlate less than this. Real frames 0.87-0.91 (PETS09, TUD-Stadtmitte), noise 0.02
#: at most.
COVERED_COHERENCE = 0.5
#: A cell matches the background when its luminance ratio is within this many stops of the frame's gain (twice the
#: widest real exposure drift measured, TUD-Stadtmitte's 0.37 stop, for what a person's shadow or a reflection moves).
MATCH_STOPS = 0.5
#: Dark below this many stops under the background's exposure: real frames stay within 0.05 (PETS09) and 0.37
#: (TUD-Stadtmitte) of it; a PETS09 bundle holds one stop down and invents people from 1.5 (docs/decisions/0013).
DARK_STOPS = 1.25
#: Overexposed above this many stops over it: the bundle holds one stop up and invents people from 1.5.
OVEREXPOSED_STOPS = 1.25
#: Blurred when the frame's sharpness (step 3) falls under this share of the background's: real frames keep 0.76 or
#: more (PETS09 1.04); a Gaussian blur of sigma 2 px leaves 0.24 at most, 0.48 with sensor noise added after it.
BLURRED_SHARPNESS = 0.5
#: Moved beyond this many frame pixels, as measured: real frames read within 0.58 px; a view moved 3 px reads 1.5 px
#: or more (coarse cells read small shifts short); a PETS09 bundle invents people from 2 px (docs/decisions/0013).
MOVED_PX = 1.5
#: A moved view is registered against the background and compensated up to this many frame pixels (the runtime moves
#: the frame back, which moves the region map with the view); beyond it the frame is ``moved``. A bracket settling or
#: a camera knocked moves the view a few pixels to a few tens; more is another view, whose perspective the bundle's
#: regions no longer fit.
REGISTRATION_BOUND_PX = 24
#: Moved when the view turned beyond this many degrees, as the halves of the cells read it (step 4): real frames read
#: within 0.07 (PETS09, TUD-Stadtmitte); a view rolled 1 degree reads 0.43 or more, half a degree 0.12-0.24. PETS09's
#: bundle holds at half a degree and invents people on the empty background from 1 (docs/decisions/0026-camera-roll.md).
ROLLED_DEG = 0.3
#: A rolled view is registered and compensated up to this many degrees (the runtime turns the frame back); beyond it
#: the frame is ``moved``. A bracket settling turns a view by a fraction of a degree, a camera knocked by a few.
REGISTRATION_BOUND_DEG = 3.0
#: A roll registered under this many degrees is left: the networks hold it (PETS09 and TUD-Stadtmitte at half a
#: degree: AP50 within 0.01 of upright, no one invented), and a view turned back costs a gather of every pixel.
REGISTERED_ROLL_DEG = 0.25
#: Rounds of the roll's registration: the cells read a small turn short (1 degree as 0.4-0.6), so they are turned back
#: by what they read and read again, until a round moves them less than :data:`ROLL_SETTLED_DEG`.
ROLL_ROUNDS = 8
ROLL_SETTLED_DEG = 0.02
#: Rounds of registration (:meth:`SceneReference.register`): the coarse cells read a shift short, so the frame is
#: moved back by what they read and measured again; three rounds bring 24 px to within a pixel, a last search of the
#: neighbouring whole pixels settles it.
REGISTRATION_ROUNDS = 4
#: A frame shows the background's view when its structure (the cells' coarse luminance less its own blur over
#: :data:`STRUCTURE_SIGMA_CELLS`: edges and texture, not the light over them) correlates with the background's at
#: least this much (step 5; a registration holds when the view moved back does): real frames 0.84-0.90 (PETS09),
#: under COCO-C's fog 0.74 and more, zoom blur 0.37; another camera's view 0.05, the view mirrored 0.07, noise 0.00
#: (docs/decisions/0017-bright-and-veiled-frames.md). The coarse luminance itself correlated 0.05 under a patchy fog.
SAME_VIEW_CORRELATION = 0.25
#: A view whose structure correlates with the background's at least this much is the background's over most of it,
#: whatever its cells' light says (step 5): real frames 0.83-0.90 (PETS09) and 0.63-0.79 (TUD-Stadtmitte's crowds),
#: COCO-C's fog 0.72 and more, PETS09 with half its view replaced by another 0.48-0.62, with 70 % of it 0.34-0.50.
KEPT_VIEW_CORRELATION = 0.6
#: The blur (Gaussian sigma, in cells) the structure is taken from: fog, glare and vignetting vary over more.
STRUCTURE_SIGMA_CELLS = 2.0
#: The phase correlation's peak must reach this for a shift to count: real frames 0.33 and more, noise and another
#: camera's view 0.10 at most.
MOVED_PEAK = 0.15
#: A matching cell's luminance ratio changes by at most this many stops to its neighbours' (step 5): a flat thing in
#: front of textured ground does not match where its light happens to be the ground's.
STRUCTURE_STOPS = 0.2
#: Changed when fewer than this share of the cells match the background: real frames 0.72 and more (TUD-Stadtmitte's
#: crowd), 0.68 a stop off; half of PETS09's view blocked reads 0.62 at most (docs/decisions/0013).
CHANGED_AGREEMENT = 0.62
#: Colour is measured on cells whose background is brighter than this (linear; about sRGB code 25): darker cells'
#: chromaticity is noise.
COLOUR_FLOOR = 0.01
#: Changed when less than this share of the background's colour variation is left: real frames keep 0.81 or more, a
#: monochrome (IR night mode) frame 0.35 at most.
COLOUR_LEFT = 0.5
#: Changed when the colour cast exceeds this (stops of R/G and B/G together): real frames 0.02 at most; white balance
#: R x1.1, B x0.9 (codes), which a PETS09 bundle holds, reads 0.45 at most; R x1.25, B x0.8, which it does not, 0.89.
COLOUR_CAST_STOPS = 0.6
#: Colour is measured on every this-many-th row and column of cells (:meth:`SceneReference._colour`).
COLOUR_STEP = 2
#: Below this colour variation (stops) the background is grey: it cannot tell a monochrome frame, and COLOUR_LEFT is
#: not measured.
MIN_COLOUR_VARIATION = 0.05
#: A background row of cells is taken to have at least this fine energy (codes squared, about a sensor's least
#: noise): a flat row (sky, a wall) does not make any detail in a frame look infinitely sharp.
MIN_FINE_ENERGY = 1.0
#: Selections with fewer cells than this fall back (to all cells) or are not measured.
MIN_CELLS = 16
#: The background's unclipped cells are split into this many bands of luminance for the veil's fit (step 2): the
#: frame's median light per band, against the band's, is a line whose offset is the airlight.
VEIL_BANDS = 8
#: Veiled beyond this share of the frame's light being airlight (fog, haze, a dome's glare; step 5): real frames fit
#: 0.05 at most (PETS09 0.03, TUD-Stadtmitte 0.05); a bundle compiled for one look was never shown more
#: (docs/decisions/0016-weather-and-gain.md).
VEIL_SHARE = 0.15
#: The veil's airlight is taken per block of this many cells a side (PETS09: 12x9 blocks of 64 px).
VEIL_BLOCK_CELLS = 8
#: A veil is taken off when the view then matches the background on this share of the cells more: a real veil
#: brings 0.2 to 0.9 (PETS09 under fog), a frame clipped two stops over or moved a few pixels 0.03 at most.
VEIL_AGREEMENT = 0.1
#: Below this share of the light, the veil's fit is its own error (real frames' exposure drift through a response not
#: quite the camera's) and no airlight is taken off.
VEIL_FLOOR = 0.03
#: Noisy beyond this per-pixel noise (8-bit codes, step 5): real frames read 2.7 at most (PETS09; TUD-Stadtmitte 0.7).
NOISE_CODES = 6.0
#: A cell's light is compared with the background's within this many standard deviations of the frame's noise
#: (step 5), on top of the bounds for the scene itself: a noisy frame's cells match within their noise.
NOISE_SIGMAS = 2.0

#: The reference's archive members (``reference/background.npz`` in a bundle).
REFERENCE_ARRAYS = ("cells", "decode", "cell_px", "fine_rows")


def cell_size(frame_size: tuple[int, int]) -> int:
    """The cell of a frame of ``frame_size`` (width, height), in pixels: :data:`REFERENCE_SHORT_SIDE` across the
    short side, at least :data:`MIN_CELL_PX`."""
    return max(MIN_CELL_PX, min(frame_size) // REFERENCE_SHORT_SIDE)


def cell_means(frame: np.ndarray, cell: int) -> np.ndarray:
    """The mean 8-bit codes of the frame's ``cell`` x ``cell`` squares, (H // cell, W // cell, 3) float32: the whole
    cells from the top-left corner (the last partial row and column of cells are left out), averaged over at most
    :data:`MAX_SAMPLES_PER_SIDE` evenly spaced rows and columns each. Summed row by row and column by column into
    16 bits: a reduction over a middle axis with a wider type costs numpy twice as much."""
    height, width = frame.shape[0] // cell, frame.shape[1] // cell
    offsets = range(0, cell, -(-cell // MAX_SAMPLES_PER_SIDE))
    rows = frame[:height * cell].reshape(height, cell, -1)
    summed = rows[:, 0].astype(np.uint16)  # at most MAX_SAMPLES_PER_SIDE x 255
    for offset in offsets[1:]:
        summed += rows[:, offset]
    columns = summed.reshape(height, frame.shape[1], 3)[:, :width * cell].reshape(height, width, cell, 3)
    means = columns[:, :, 0].astype(np.float32)
    for offset in offsets[1:]:
        means += columns[:, :, offset]
    return means / np.float32(len(offsets) ** 2)


def fine_energy(frame: np.ndarray, cell: int) -> np.ndarray:
    """Per sampled row of cells (every :data:`FINE_ROW_STEP`-th), the mean squared difference of neighbouring pixels
    across and down, (ceil(H // cell / FINE_ROW_STEP),) float32: the green channel (the most of luminance) on the cell
    row's first three pixel rows, so that both vertical pairings (even-odd and odd-even rows, which differ on an
    interlaced camera) are in it; 3/16 of PETS09's pixels. Per cell row, so that a band of a few rows (a frame
    border, a caption: TUD-Stadtmitte's bottom rows hold a third of its fine energy) is one outvoted row of the
    median that compares it with the background's."""
    height = frame.shape[0] // cell
    green = frame[:height * cell, :, 1].reshape(height, cell, -1)
    taken = green[::FINE_ROW_STEP, :min(3, cell)].astype(np.float32)  # (rows, 3, W)
    across = taken[:, :, 1:] - taken[:, :, :-1]
    down = taken[:, 1:] - taken[:, :-1]
    return np.einsum("rkw,rkw->r", across, across) / np.float32(max(across[0].size, 1)) \
        + np.einsum("rkw,rkw->r", down, down) / np.float32(max(down[0].size, 1))


def clipped_cells(cells: np.ndarray) -> np.ndarray:
    """Cells with a channel at or above :data:`CLIPPED_CODE` (channel by channel: numpy reduces a last axis of three
    thirty times slower)."""
    return np.maximum(np.maximum(cells[..., 0], cells[..., 1]), cells[..., 2]) >= CLIPPED_CODE


def _coarse_energy(luma: np.ndarray) -> float:
    across, down = np.diff(luma, axis=1), np.diff(luma, axis=0)
    return float((np.mean(across ** 2) if across.size else 0.0) + (np.mean(down ** 2) if down.size else 0.0))


def _coherence(luma: np.ndarray, energy: float) -> float:
    """Correlation of neighbouring cells, ``1 - mean squared difference / (2 variance)`` (0 for a flat frame)."""
    variance = float(luma.var())
    return 0.0 if variance <= 1e-6 else 1.0 - (energy / 2.0) / (2.0 * variance)


def _smoothed(luma: np.ndarray, sigma: float = STRUCTURE_SIGMA_CELLS) -> np.ndarray:
    """``luma`` blurred by a Gaussian of ``sigma`` cells (separable; edges mirrored)."""
    radius = max(1, math.ceil(3 * sigma))
    taps = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma) ** 2).astype(np.float32)
    for axis in (0, 1):
        reach = min(radius, luma.shape[axis] - 1)
        if reach < 1:
            continue
        weights = taps[radius - reach:radius + reach + 1] / taps[radius - reach:radius + reach + 1].sum()
        rows = luma if axis == 0 else luma.T
        padded = np.pad(rows, ((reach, reach), (0, 0)), mode="reflect")
        blurred = weights[0] * padded[:rows.shape[0]]
        for offset in range(1, len(weights)):
            blurred += weights[offset] * padded[offset:offset + rows.shape[0]]
        luma = blurred if axis == 0 else blurred.T
    return luma


def _structure(luma: np.ndarray) -> np.ndarray:
    """The cells' luminance less its blur (:data:`STRUCTURE_SIGMA_CELLS`): what a veil, a glare or a change of light
    over the view leaves of the scene, and another view does not have."""
    return luma - _smoothed(luma)


def _log_chroma(linear: np.ndarray) -> np.ndarray:
    """(..., 2): log2 of R/G and B/G in linear light."""
    return np.log2((linear[..., [0, 2]] + LINEAR_FLOOR) / (linear[..., 1:2] + LINEAR_FLOOR))


def fitted_line(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares gain and offset of ``y = gain x + offset``; (0, 0) when ``x`` does not vary (a background of
    one light has no line to fit)."""
    spread = float(np.var(x))
    if spread <= 1e-12:
        return 0.0, 0.0
    gain = float(np.mean((x - x.mean()) * (y - y.mean()))) / spread
    return gain, float(y.mean()) - gain * float(x.mean())


@dataclass(frozen=True)
class FitRange:
    """How far a frame may depart from the background and still be fit: what the bundle's networks were compiled to
    see. The defaults are a bundle compiled for the background's one look (docs/decisions/0013-scene-fitness.md); a
    bundle compiled over a camera range (:mod:`vc.model.camera_range`) carries its own, measured at export on the
    background rendered at the range's ends (docs/decisions/0014-camera-range.md)."""

    dark_stops: float = DARK_STOPS
    overexposed_stops: float = OVEREXPOSED_STOPS
    blurred_sharpness: float = BLURRED_SHARPNESS
    colour_cast_stops: float = COLOUR_CAST_STOPS
    monochrome: bool = False  # a monochrome frame (an IR night mode) is fit
    veil_share: float = VEIL_SHARE
    noise_codes: float = NOISE_CODES
    changed_agreement: float = CHANGED_AGREEMENT

    def __post_init__(self) -> None:
        for name in ("dark_stops", "overexposed_stops", "blurred_sharpness", "colour_cast_stops", "veil_share",
                     "noise_codes", "changed_agreement"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value) \
                    or value < 0:
                raise ValueError(f"{name} must be a finite number, not negative (got {value!r})")
        if not isinstance(self.monochrome, bool):
            raise ValueError(f"monochrome must be true or false (got {self.monochrome!r})")

    @classmethod
    def from_dict(cls, data: object) -> FitRange:
        """The range a bundle's manifest stores (:meth:`to_dict`); a ValueError names what is wrong."""
        if not isinstance(data, dict):
            raise ValueError(f"expected a mapping, got {type(data).__name__}")
        unknown = sorted(set(data) - set(cls.__dataclass_fields__))
        if unknown:
            raise ValueError(f"unknown field(s) {', '.join(unknown)}")
        return cls(**data)

    def to_dict(self) -> dict:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


#: The range of a bundle that carries none: its background's one look.
BACKGROUND_ONLY = FitRange()


@dataclass(frozen=True)
class FrameFitness:
    """A frame's state (:data:`STATES`) and the numbers that decided it (None where not measured: every number of
    an ``unknown`` frame, the colour numbers of a grey background)."""

    state: str
    reason: str = ""
    spread: float | None = None  # coarse luminance variation / the background's
    coherence: float | None = None  # correlation of neighbouring cells
    exposure_stops: float | None = None  # frame's light over the background's, on the matching cells
    matching: float | None = None  # share of cells that match the background: its light under that gain, its structure
    sharpness: float | None = None  # fine gradient energy / the background's, over the squared spread
    shift_px: tuple[float, float] | None = None  # (x, y): how far the frame's content moved from the background's
    shift_peak: float | None = None  # the phase correlation's peak (1: the same picture)
    colour_left: float | None = None  # colour variation / the background's (None for a grey background)
    colour_cast_stops: float | None = None  # chromaticity offset from the background
    veil: float | None = None  # share of the frame's light that is airlight (fog, haze, glare)
    noise_codes: float | None = None  # per-pixel noise beyond the background's, 8-bit codes
    correlation: float | None = None  # of the coarse luminance with the background's
    roll_deg: float | None = None  # how far the content turned from the background's, counter-clockwise, as read
    registered_px: tuple[int, int] | None = None  # (x, y): the view's move the runtime compensated (None: none)
    registered_roll_deg: float | None = None  # the view's roll the runtime compensated (None: none)
    exposure_corrected_stops: float | None = None  # the exposure change the runtime gave the frame (vc.deploy.exposure)
    veil_taken_off: float | None = None  # the veil's share of the light the runtime stretched away (vc.deploy.veil)

    @property
    def unfit(self) -> bool:
        return self.state in UNFIT_STATES

    @classmethod
    def unknown(cls, reason: str) -> FrameFitness:
        return cls(UNKNOWN, reason)

    def to_dict(self) -> dict:
        """JSON-ready: the state, the reason of an unfit one, and the numbers measured (rounded)."""
        result: dict = {"state": self.state}
        if self.unfit:
            result["reason"] = self.reason
        for name in ("spread", "coherence", "exposure_stops", "matching", "sharpness", "shift_peak", "colour_left",
                     "colour_cast_stops", "veil", "noise_codes", "correlation", "roll_deg", "registered_roll_deg"):
            value = getattr(self, name)
            if value is not None:
                result[name] = round(float(value), 3)
        if self.shift_px is not None:
            result["shift_px"] = [round(float(value), 2) for value in self.shift_px]
        if self.registered_px is not None:
            result["registered_px"] = [int(value) for value in self.registered_px]
        if self.exposure_corrected_stops is not None:
            result["exposure_corrected_stops"] = round(float(self.exposure_corrected_stops), 3)
        if self.veil_taken_off is not None:
            result["veil_taken_off"] = round(float(self.veil_taken_off), 3)
        return result


@dataclass(frozen=True, eq=False)
class SceneReference:
    """The background as the fitness measurements need it (module docstring): ``cells`` (h, w, 3) float32 mean
    codes of ``cell_px`` squares, ``decode`` (256,) the camera response's code -> linear light, ``fine_rows`` (h,)
    the background's :func:`fine_energy`. Built from the background image with :meth:`of_background`, stored with
    :meth:`to_bytes`, read back (and checked) with :meth:`from_bytes`."""

    cells: np.ndarray
    decode: np.ndarray
    cell_px: int
    fine_rows: np.ndarray
    _derived: dict = field(default_factory=dict, init=False, repr=False)

    @classmethod
    def of_background(cls, background: np.ndarray, decode: np.ndarray) -> SceneReference:
        """The reference of a background image ((H, W, 3) uint8 RGB, the camera's frame) whose codes ``decode``
        ((256,) linear light per code) turns into light."""
        cell = cell_size((background.shape[1], background.shape[0]))
        return cls(cell_means(background, cell), np.asarray(decode, np.float32), cell, fine_energy(background, cell))

    def to_bytes(self) -> bytes:
        buffer = io.BytesIO()
        np.savez(buffer, cells=self.cells.astype(np.float32), decode=self.decode.astype(np.float32),
                 cell_px=np.int64(self.cell_px), fine_rows=self.fine_rows.astype(np.float32))
        return buffer.getvalue()

    @classmethod
    def from_bytes(cls, data: bytes, frame_size: tuple[int, int]) -> SceneReference:
        """Read and check a stored reference for frames of ``frame_size`` (width, height); a ValueError says what is
        wrong with it."""
        try:
            with np.load(io.BytesIO(data), allow_pickle=False) as archive:
                missing = [name for name in REFERENCE_ARRAYS if name not in archive.files]
                if missing:
                    raise ValueError(f"lacks the array(s) {', '.join(missing)}")
                arrays = {name: archive[name] for name in REFERENCE_ARRAYS}
        except (OSError, EOFError, zipfile.BadZipFile, KeyError, ValueError) as error:
            if str(error).startswith("lacks"):
                raise
            # numpy takes bytes that are not an archive for pickled data, which is never loaded
            detail = "pickled data is never loaded" if "pickle" in str(error) else str(error)
            raise ValueError(f"not a readable numpy archive ({detail})") from None
        cells, decode, fine = arrays["cells"], arrays["decode"], arrays["fine_rows"]
        if arrays["cell_px"].shape != () or not np.issubdtype(arrays["cell_px"].dtype, np.integer):
            raise ValueError("cell_px is not one integer")
        cell, expected_cell = int(arrays["cell_px"]), cell_size(frame_size)
        expected = (frame_size[1] // expected_cell, frame_size[0] // expected_cell, 3)
        if cell != expected_cell or cells.shape != expected:
            raise ValueError(f"cells of {cell} px in a {cells.shape} array do not fit the bundle's "
                             f"{frame_size[0]}x{frame_size[1]} frames ({expected_cell} px cells, {expected})")
        for name, array in (("cells", cells), ("decode", decode), ("fine_rows", fine)):
            if not np.issubdtype(array.dtype, np.floating) or not np.isfinite(array).all():
                raise ValueError(f"{name} must hold finite numbers")
        if cells.min() < 0 or cells.max() > 255:
            raise ValueError("cells must be codes between 0 and 255")
        if decode.shape != (256,) or decode[0] < 0 or np.any(np.diff(decode) < 0) or decode[-1] <= decode[0]:
            raise ValueError("decode must be 256 non-negative, rising values (the camera response)")
        rows = len(range(0, expected[0], FINE_ROW_STEP))
        if fine.shape != (rows,) or fine.min() < 0:
            raise ValueError(f"fine_rows must be {rows} non-negative numbers, one per sampled row of cells")
        return cls(cells.astype(np.float32), decode.astype(np.float32), cell, fine.astype(np.float32))

    def _linear(self, cells: np.ndarray) -> np.ndarray:
        """Cells' mean codes -> linear light, interpolating the decoding table between codes."""
        table = self.derived["table"]
        index = cells.astype(np.int32)  # codes 0-255: 255 takes the table's repeated last entry
        low = table[index]
        return low + (cells - index) * (table[index + 1] - low)

    def __post_init__(self) -> None:
        self._derive()

    @property
    def derived(self) -> dict:
        """What every frame is compared with, computed once, when the reference is made (frames may be measured
        from several threads)."""
        return self._derived

    def _derive(self) -> None:
        self._derived["table"] = np.append(self.decode, self.decode[-1]).astype(np.float32)
        luma, linear = self.cells @ LUMA, self._linear(self.cells)
        luminance = linear @ LUMA
        window = hann_window(luma.shape)
        bright = (luminance > COLOUR_FLOOR)[::COLOUR_STEP, ::COLOUR_STEP]
        self._derived["bright"] = luminance > COLOUR_FLOOR
        chroma = _log_chroma(linear[::COLOUR_STEP, ::COLOUR_STEP])
        enough = np.count_nonzero(bright) >= MIN_CELLS
        centre = np.median(chroma[bright], axis=0) if enough else np.zeros(2)
        variation = float(np.median(np.linalg.norm(chroma[bright] - centre, axis=1))) if enough else 0.0
        clipped = clipped_cells(self.cells)
        usable = luminance[~clipped]
        edges = np.quantile(usable, np.linspace(0.0, 1.0, VEIL_BANDS + 1)[1:-1]) if usable.size >= MIN_CELLS \
            else np.zeros(0)
        band = np.searchsorted(edges, luminance)
        bands = [(band == index) & ~clipped for index in range(len(edges) + 1)]
        bands = [cells for cells in bands if np.count_nonzero(cells) >= MIN_CELLS]
        samples = len(range(0, self.cell_px, -(-self.cell_px // MAX_SAMPLES_PER_SIDE))) ** 2
        self._derived.update(
            bands=bands, band_light=np.array([float(np.median(luminance[cells])) for cells in bands], np.float64),
            band_channels=np.array([[float(np.median(linear[..., channel][cells])) for channel in range(3)]
                                    for cells in bands], np.float64).reshape(-1, 3),
            slope=np.append(np.diff(self.decode), self.decode[-1] - self.decode[-2]).astype(np.float32),
            samples=samples,
            luma=luma, structure=_structure(luma), luminance=luminance, window=window,
            conjugate=spectrum(luma, window), halves=HalvesReference(luma), spread=max(float(luma.std()), 1e-3),
            colour_cells=bright, colour_chroma=chroma,
            colour_variation=variation,
            clipped=clipped, fine_rows=np.maximum(self.fine_rows, MIN_FINE_ENERGY))

    def fitness(self, frame: np.ndarray, fit_range: FitRange = BACKGROUND_ONLY) -> FrameFitness:
        """The fitness of an (H, W, 3) uint8 RGB frame of the bundle's camera (module docstring), within
        ``fit_range`` (what the bundle was compiled to see)."""
        reference = self.derived
        cells = cell_means(frame, self.cell_px)
        luma, linear = cells @ LUMA, self._linear(cells)
        energy = _coarse_energy(luma)
        spread = float(luma.std()) / reference["spread"]
        coherence = _coherence(luma, energy)

        unclipped = ~(reference["clipped"] | clipped_cells(cells))
        light = linear @ LUMA
        fine_rows = fine_energy(frame, self.cell_px)
        fine = float(np.median(fine_rows / reference["fine_rows"]))
        sharpness = fine / spread ** 2 if spread > 1e-3 else 0.0
        noise = math.sqrt(max(float(np.median(fine_rows - spread ** 2 * self.fine_rows)), 0.0) / 4.0)
        # a cell's light is a mean of `samples` pixels: its noise, in codes of its luma
        code_noise = np.float32(noise / math.sqrt(reference["samples"])) \
            * reference["slope"][np.clip(luma.astype(np.int32), 0, 255)]

        exposure, matching_cells = self._agreement(light, unclipped, code_noise)
        scene, veil = linear, 0.0
        airlight, share = self._veil(linear, light, unclipped)
        if share >= VEIL_FLOOR:
            # a veil is taken off only when the view then matches the background clearly better: a moved view, another
            # view and a clipped one also fit a flatter line, and match no better for it
            veiled_scene = np.clip(linear - airlight, 0.0, None)
            veiled_exposure, veiled_cells = self._agreement(veiled_scene @ LUMA, unclipped, code_noise)
            if np.count_nonzero(veiled_cells) > np.count_nonzero(matching_cells) + VEIL_AGREEMENT * matching_cells.size:
                scene, veil, exposure, matching_cells = veiled_scene, share, veiled_exposure, veiled_cells
        matching = float(np.mean(matching_cells))

        shift, peak = self._shift(luma)
        roll = reference["halves"].roll(luma, MOVED_PEAK)

        colour_left, cast = self._colour(scene, matching_cells & unclipped)
        if veil > 0.0 and cast is not None:
            # the veil's colour is a fit, and taking off too much of it inflates the scene's colours: a cast is one
            # the frame reads with the veil taken off and as it is (a grey veil greys it, which is no cast)
            as_is = self._colour(linear, matching_cells & unclipped)
            if as_is[1] is not None and as_is[1] < cast:
                colour_left, cast = as_is

        correlation = self._correlation(luma)
        state, reason = self._decide(fit_range, spread, coherence, exposure, sharpness, shift, peak, roll, matching,
                                     colour_left, cast, veil, noise, correlation)
        return FrameFitness(state, reason, spread, coherence, exposure, matching, sharpness, shift, peak, colour_left,
                            cast, veil, noise, correlation, roll_deg=roll)

    def _agreement(self, light: np.ndarray, unclipped: np.ndarray, code_noise: np.ndarray) -> tuple[float,
                                                                                                     np.ndarray]:
        """The frame's exposure against the background (step 2) and the cells that match it (step 5), for the
        scene's light ``light`` (linear luminance per cell) whose cells carry ``code_noise`` (their noise, linear
        light)."""
        reference = self.derived
        ratio = np.log2((light + LINEAR_FLOOR) / (reference["luminance"] + LINEAR_FLOOR))
        usable = ratio[unclipped] if np.count_nonzero(unclipped) >= MIN_CELLS else ratio.ravel()
        first = float(np.median(usable))
        following = usable[np.abs(usable - first) < MATCH_STOPS]
        exposure = float(np.median(following)) if following.size >= MIN_CELLS else first
        cell_noise = code_noise / ((light + LINEAR_FLOOR) * np.float32(math.log(2)))  # in stops
        matching = (np.abs(ratio - exposure) < MATCH_STOPS + NOISE_SIGMAS * cell_noise) \
            & self._same_structure(ratio, unclipped, cell_noise)
        return exposure, matching

    def _veil(self, linear: np.ndarray, light: np.ndarray, unclipped: np.ndarray) -> tuple[np.ndarray, float]:
        """The airlight (linear, (h, w, 3) per cell) a veil adds to the frame, and its share of the frame's light
        (step 2): the frame's median light in each band of the background's luminance (:data:`VEIL_BANDS`), fitted
        as a line against the band's; its offset, when positive, is light that follows no part of the scene. Fog is
        patchy and glare falls off, so the light the line leaves over the scene's is then taken block by block
        (:data:`VEIL_BLOCK_CELLS`, the median: people are a minority of a block); its colour is the offsets of the
        same fit channel by channel (a haze takes the sky's colour). Under :data:`VEIL_FLOOR` of the light the
        offset is the fit's own error and taken as none (zero airlight)."""
        reference = self.derived
        none = np.zeros(1, np.float32)
        kept = [cells & unclipped for cells in reference["bands"]]
        usable = [index for index, cells in enumerate(kept) if np.count_nonzero(cells) >= MIN_CELLS]
        if len(usable) < 3:
            return none, 0.0
        frame_light = np.array([float(np.median(light[kept[index]])) for index in usable])
        gain, offset = fitted_line(reference["band_light"][usable], frame_light)
        share = min(max(offset, 0.0) / max(float(frame_light.mean()), LINEAR_FLOOR), 1.0)
        if gain <= 0 or share < VEIL_FLOOR:
            return none, share
        channel_offsets = np.array([fitted_line(reference["band_channels"][usable, channel],
                                          np.array([float(np.median(linear[..., channel][kept[index]]))
                                                    for index in usable]))[1] for channel in range(3)])
        colour = np.clip(channel_offsets, 0.0, None) / max(float(offset), LINEAR_FLOOR)
        left = light - np.float32(gain) * reference["luminance"]
        block = VEIL_BLOCK_CELLS
        height, width = (left.shape[0] // block) * block, (left.shape[1] // block) * block
        if height == 0 or width == 0:
            return (np.float32(min(offset, frame_light.min())) * colour).astype(np.float32), share
        blocks = np.median(left[:height, :width].reshape(height // block, block, width // block, block)
                           .transpose(0, 2, 1, 3).reshape(height // block, width // block, -1), axis=2)
        rows = np.minimum(np.arange(left.shape[0]) // block, blocks.shape[0] - 1)
        columns = np.minimum(np.arange(left.shape[1]) // block, blocks.shape[1] - 1)
        airlight = np.clip(blocks[rows][:, columns], 0.0, None)[..., None] * colour
        return airlight.astype(np.float32), share

    def _same_structure(self, ratio: np.ndarray, unclipped: np.ndarray, cell_noise: np.ndarray) -> np.ndarray:
        """Cells whose luminance ratio to the background changes by at most :data:`STRUCTURE_STOPS` to their right
        and lower neighbours (and their noise, ``cell_noise`` stops, :data:`NOISE_SIGMAS` times): the frame's light
        follows the background's from cell to cell, so the cell shows the background's structure. Tested between
        cells bright enough to have one (:data:`COLOUR_FLOOR`) and unclipped; the others pass."""
        tested = self.derived["bright"] & unclipped
        same = np.ones(ratio.shape, bool)
        spread = np.float32(NOISE_SIGMAS * math.sqrt(2.0))
        across = (np.abs(np.diff(ratio, axis=1))
                  > STRUCTURE_STOPS + spread * np.maximum(cell_noise[:, 1:], cell_noise[:, :-1])) \
            & tested[:, 1:] & tested[:, :-1]
        down = (np.abs(np.diff(ratio, axis=0))
                > STRUCTURE_STOPS + spread * np.maximum(cell_noise[1:], cell_noise[:-1])) & tested[1:] & tested[:-1]
        same[:, :-1] &= ~across
        same[:-1] &= ~down
        return same

    def _shift(self, luma: np.ndarray) -> tuple[tuple[float, float], float]:
        """Phase correlation of the frame's coarse luminance with the background's: (x, y) frame pixels and the
        peak."""
        x, y, peak = phase_correlation(luma, self.derived["window"], self.derived["conjugate"])
        return (x * self.cell_px, y * self.cell_px), peak

    def register(self, frame: np.ndarray, bound_px: float = REGISTRATION_BOUND_PX,
                 bound_deg: float = REGISTRATION_BOUND_DEG) -> Registration | None:
        """How the view of ``frame`` moved from the background's (:mod:`vc.deploy.registration`): whole frame pixels
        up to ``bound_px`` and a roll up to ``bound_deg``; None when the correlation says nothing (an unrelated
        picture: the phase correlation's peak under :data:`MOVED_PEAK`, or the view undone correlating under
        :data:`SAME_VIEW_CORRELATION`) or the view moved beyond the bounds. The frame is moved back by what the
        coarse cells read and read again (:data:`REGISTRATION_ROUNDS`), and turned back by the roll its cells read
        and read again (:data:`ROLL_ROUNDS`; a roll under :data:`REGISTERED_ROLL_DEG` is left); then the
        neighbouring whole pixels, with the roll and without, are compared by the correlation of their cells'
        luminance with the background's."""
        shift = np.zeros(2, np.int64)
        for _ in range(REGISTRATION_ROUNDS):
            (x, y), peak = self._shift(cell_means(translated(frame, tuple(shift)), self.cell_px) @ LUMA)
            if peak < MOVED_PEAK:
                return None
            step = np.array([round(x), round(y)], np.int64)
            if not step.any():
                break
            shift += step
            if math.hypot(*shift) > bound_px + self.cell_px:
                return None
        roll = self._roll(frame, (int(shift[0]), int(shift[1])))
        if abs(roll) > bound_deg:
            return None
        rolls = (roll, 0.0) if abs(roll) >= REGISTERED_ROLL_DEG else (0.0,)
        candidates = [Registration(int(shift[0] + dx), int(shift[1] + dy), turn)
                      for turn in rolls for dy in (-1, 0, 1) for dx in (-1, 0, 1)]
        correlation, best = max((self._luma_correlation(view_back(frame, candidate)), index)
                                for index, candidate in enumerate(candidates))
        registration = candidates[best]
        within = math.hypot(*registration.shift) <= bound_px
        return registration if within and correlation >= SAME_VIEW_CORRELATION else None

    def _roll(self, frame: np.ndarray, shift: tuple[int, int]) -> float:
        """The roll of the view of ``frame`` moved by ``shift``, degrees: the view is turned back by what its halves
        read (short for a small turn) and read again until it settles."""
        halves, roll = self.derived["halves"], 0.0
        for _ in range(ROLL_ROUNDS):
            view = view_back(frame, Registration(*shift, roll))
            step = halves.roll(cell_means(view, self.cell_px) @ LUMA, MOVED_PEAK)
            roll += step
            if abs(step) < ROLL_SETTLED_DEG or abs(roll) > 2 * REGISTRATION_BOUND_DEG:
                break
        return roll

    def _luma_correlation(self, frame: np.ndarray) -> float:
        return self._correlation(cell_means(frame, self.cell_px) @ LUMA)

    def _correlation(self, luma: np.ndarray) -> float:
        """Correlation of the structure of the cells' coarse luminance (:func:`_structure`) with the background's."""
        reference = self.derived["structure"]
        frame = _structure(luma)
        frame_centred, reference_centred = frame - frame.mean(), reference - reference.mean()
        scale = float(np.sqrt((frame_centred ** 2).sum() * (reference_centred ** 2).sum()))
        return float((frame_centred * reference_centred).sum()) / scale if scale > 0 else 0.0

    def _colour(self, linear: np.ndarray, matching: np.ndarray) -> tuple[float | None, float | None]:
        """Colour left (None for a grey background) and cast, on the matching cells bright enough to have colour, of
        every other row and column of cells (PETS09: 1 700 cells, plenty for a median, at a quarter of the cost).
        A veil, fog or snow takes colour away toward grey (log chromaticity 0), which moves the colours' centre
        without a white balance: the cast is measured against the background's chromaticities scaled by the colour
        left (at most 1; docs/decisions/0017-bright-and-veiled-frames.md)."""
        reference = self.derived
        cells = matching[::COLOUR_STEP, ::COLOUR_STEP] & reference["colour_cells"]
        if np.count_nonzero(cells) < MIN_CELLS:
            return None, None
        chroma = _log_chroma(linear[::COLOUR_STEP, ::COLOUR_STEP][cells])
        background = reference["colour_chroma"][cells]
        if reference["colour_variation"] < MIN_COLOUR_VARIATION:
            return None, float(np.hypot(*np.median(chroma - background, axis=0)))
        centre = np.median(chroma, axis=0)
        left = float(np.median(np.linalg.norm(chroma - centre, axis=1))) / reference["colour_variation"]
        return left, float(np.hypot(*np.median(chroma - min(left, 1.0) * background, axis=0)))

    @staticmethod
    def _decide(fit: FitRange, spread: float, coherence: float, exposure: float, sharpness: float,
                shift: tuple[float, float], peak: float, roll: float, matching: float, colour_left: float | None,
                cast: float | None, veil: float, noise: float, correlation: float) -> tuple[str, str]:
        if spread < COVERED_SPREAD:
            return COVERED, f"no scene: {spread:.2f} of the background's contrast (covered below {COVERED_SPREAD})"
        if coherence < COVERED_COHERENCE:
            return COVERED, (f"no scene: neighbouring cells correlate {coherence:.2f} (noise; covered below "
                             f"{COVERED_COHERENCE})")
        if exposure < -fit.dark_stops:
            return DARK, f"{exposure:+.1f} stops against the background (dark below {-fit.dark_stops:+.2f})"
        if exposure > fit.overexposed_stops:
            return OVEREXPOSED, f"{exposure:+.1f} stops against the background (overexposed above " \
                                f"{fit.overexposed_stops:+.2f})"
        if sharpness < fit.blurred_sharpness:
            return BLURRED, f"{sharpness:.2f} of the background's fine detail (blurred below " \
                            f"{fit.blurred_sharpness:.2f})"
        distance = math.hypot(*shift)
        if distance > MOVED_PX and peak >= MOVED_PEAK:
            return MOVED, f"moved {distance:.1f} px from the background (bound {MOVED_PX:g} px)"
        if abs(roll) > ROLLED_DEG and peak >= MOVED_PEAK:
            return MOVED, f"turned {roll:+.2f} degrees from the background, as read (bound {ROLLED_DEG:g})"
        if veil > fit.veil_share:
            return CHANGED, f"{veil:.2f} of the light is a veil's (fog, haze, glare; changed above " \
                            f"{fit.veil_share:.2f})"
        if noise > fit.noise_codes:
            return CHANGED, f"noise of {noise:.1f} codes (changed above {fit.noise_codes:.1f})"
        if correlation < SAME_VIEW_CORRELATION:
            return CHANGED, f"the view correlates {correlation:.2f} with the background's (another view below " \
                            f"{SAME_VIEW_CORRELATION})"
        if matching < fit.changed_agreement and correlation < KEPT_VIEW_CORRELATION:
            return CHANGED, f"{matching:.2f} of the view matches the background and its structure correlates " \
                            f"{correlation:.2f} (changed below {fit.changed_agreement:.2f} and " \
                            f"{KEPT_VIEW_CORRELATION})"
        if colour_left is not None and colour_left < COLOUR_LEFT and not fit.monochrome:
            return CHANGED, f"{colour_left:.2f} of the background's colour left (monochrome; changed below " \
                            f"{COLOUR_LEFT})"
        if cast is not None and cast > fit.colour_cast_stops and not (fit.monochrome and colour_left is not None
                                                                        and colour_left < COLOUR_LEFT):
            return CHANGED, f"colour cast {cast:.2f} stops (white balance; changed above " \
                            f"{fit.colour_cast_stops:.2f})"
        return OK, ""
