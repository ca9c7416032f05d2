"""Heat maps -> people (numpy only: evaluation and the appliance decode identically).

1. People are the local maxima of the centre map above ``centre_threshold`` (3x3 neighbourhood), refined to
   sub-cell precision by a parabola through each peak and its neighbours. A peak closer than
   ``min_centre_separation`` expected heights to a stronger one is that person's blurred peak, not another.
   Asked for weak people (``weak_above``), the peaks down to that value are decoded too, flagged ``weak``, for a
   tracker to continue tracks with; they take no mask cells or keypoint peaks from the others. A network's fine
   centre map (:data:`~vc.deploy.heatmaps.FINE_CENTRE_CHANNELS`) is not read: it trains the network, and the
   coarse map's peaks track people best (docs/decisions/0010-fine-centre-map.md).
   1b. From a network with centre offsets, each mask cell above ``mask_threshold`` votes for the centre of the
   person it belongs to (cell + offset x expected height). Votes that no centre of step 1 claims (within
   ``vote_separation``) and that gather at least ``vote_support`` of a person's pixels around one point are
   a person the centre map merged into a neighbour's peak, or blurred between people: a peak few pixels vote for
   moves there, else they are added at their votes' mean, scored by the centre map there.
2. Each keypoint is a peak of its map weighted by a Gaussian prior around where that keypoint sits on an
   upright person (:data:`UPRIGHT_PRIOR`, scaled by the person's expected height): a neighbour's ankle, even
   if nearer to this centre, loses to this person's own. The candidates are the local maxima of each keypoint
   map, shared out greedily, best prior-weighted value first: a peak goes to one person only, so two people side
   by side never both take the stronger one's wrist. A weak person takes the maximum of each map weighted by
   their prior, whoever else has it. At most ``max_people`` peaks are decoded. Pairs come in image order and the
   handedness maps at the person's centre say which member is the left one (:mod:`vc.deploy.heatmaps`).
3. The mask cells above ``mask_threshold`` go to the nearest centre (in units of expected height); with centre
   offsets, to the centre nearest the one they vote for.
4. The box is scene-specific: its top and bottom are the person's own head and feet where their keypoints are
   confident and agree with the expected height of a person at that image position (the region's camera knows
   it; ``expected_height_px``), else that expected height centred on the centre peak (the point half the stature
   above the feet); its width spans the person's confident keypoints and mask cells.
5. From a network with a head map (:data:`~vc.deploy.heatmaps.HEAD_CHANNELS`), steps 1-4 run a second time on the
   heads: the head map's peaks, none merged (heads stand apart where centres blur), each a person whose centre is
   the head plus the centre offset there times the size map's height; in step 1b each cell's offset is scaled by
   the size map's height there. The box's top and bottom are step 4's where the height they give agrees with the
   size map's within :data:`HEAD_HEIGHT_AGREEMENT`, else the size map's height centred on the centre: a person's own
   head and ankles place the box better than the size map, but at eye level a person behind another stands above
   the other's ankles, and the size map then says how tall they are
   (docs/decisions/0060-the-heads-boxes-from-their-keypoints.md). A strong person of this reading is added where
   their box overlaps every strong person of the first that the caller keeps (a region: those standing in its owned
   area) by less than :data:`HEAD_UNION_IOU` (:func:`with_heads_added`), and then dropped where their head (their
   box's top middle) lies within :data:`SAME_HEAD_REACH` of another reported person's height of that person's head
   (:func:`one_head_each`: one head, one person; the runtime applies it over the frame). Their mask cells are those
   the head reading gives them: a cell may belong to a person of each reading, as to a strong person and a weak one
   (the tracker's appearance reads them). People in a group whose centres make one peak are so found, each with
   their own box (docs/decisions/0058-a-head-map-in-every-region.md).

Coordinates are network-input pixels (pixel centres at integers) unless named ``*_cells``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.heatmaps import (
    ANATOMICAL_CHANNELS,
    CENTRE_CHANNEL,
    CENTRE_OFFSET_CHANNELS,
    HANDEDNESS_CHANNELS,
    HEAD_CHANNEL,
    HEAD_CHANNELS,
    KEYPOINT_CHANNELS,
    LAYOUTS,
    MASK_CHANNEL,
    OFFSET_CHANNELS,
    SIZE_CHANNEL,
    SIZE_UNIT_CELLS,
    cells_to_input,
    swap_pairs,
)
from vc.keypoints import COCO_KEYPOINTS

#: Where each COCO keypoint sits on an upright person, below (+) or above (-) the centre, in person heights
#: (surveillance views of pedestrians: heads up, feet down; the prior's width absorbs gait and lean): the median
#: over 2 000 sampled walkers and standers, dressed in the default wardrobe (hair, clothes and soles as volume,
#: :mod:`vc.render.dressing`), of (keypoint - middle of the body's vertical extent) / that extent, at the seen
#: level. Measured, not guessed: guessed offsets made the boxes about 5 % short
#: (docs/decisions/0003-decoder-settings.md; dressed: docs/decisions/0005-dressed-people.md). ``tests/test_bodies.py``
#: checks them against dressed anny bodies.
UPRIGHT_OFFSETS = np.array([-0.41, -0.43, -0.43, -0.42, -0.42, -0.305, -0.305, -0.155, -0.155, -0.02, -0.02,
                            -0.02, -0.02, 0.195, 0.195, 0.41, 0.41])
#: The mask area of an upright person, in squared person heights: about half of a box 0.37 heights wide (COCO
#: pedestrians' masks fill about half their boxes). It turns a cluster of votes into a share of one person.
PERSON_AREA = 0.18
#: A centre peak that few pixels vote for, this close (person heights) to where votes put a person, is the blur of
#: the people around it (step 1b): two people side by side blur into a peak about a quarter height from each.
MERGED_PEAK_REACH = 0.5
#: The lower of a person's two ankles, measured likewise (0.439 bare): the planted foot's, which the box's bottom
#: follows (the other foot swings up to 0.1 heights higher).
LOWER_ANKLE_OFFSET = 0.427
#: Step 5 adds a person read from the heads whose box overlaps every person of the first reading by less than this:
#: more, and it is one of them (docs/decisions/0058-a-head-map-in-every-region.md).
HEAD_UNION_IOU = 0.5
#: A person added from the heads whose head lies within this many of another person's heights of that person's head
#: is that person again (step 5; docs/decisions/0058-a-head-map-in-every-region.md).
SAME_HEAD_REACH = 0.1
#: Step 5 keeps step 4's top and bottom for a person read from the heads where the height they give is within this
#: factor of the size map's (docs/decisions/0060-the-heads-boxes-from-their-keypoints.md).
HEAD_HEIGHT_AGREEMENT = 1.15


@dataclass(frozen=True)
class UprightPrior:
    """Where an upright person's keypoints lie: :data:`UPRIGHT_OFFSETS` and :data:`LOWER_ANKLE_OFFSET` together, a
    parameter of :func:`decode` so that another body model's prior can be measured without touching these."""

    offsets: np.ndarray  # (17,) person heights from the middle of the body's vertical extent, down positive
    lower_ankle: float


#: The prior every bundle decodes with.
UPRIGHT_PRIOR = UprightPrior(UPRIGHT_OFFSETS, LOWER_ANKLE_OFFSET)


@dataclass(frozen=True)
class DecodeConfig:
    """How heat maps become people; a bundle's manifest carries it per region (fields it lacks take these
    defaults). Lengths in person heights are fractions of the expected height at the person's centre. The values
    and the options measured against them: docs/decisions/0003-decoder-settings.md."""

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    stride: int = 4
    centre_threshold: float = 0.3
    keypoint_threshold: float = 0.2  # keypoints below this confidence do not shape the box
    mask_threshold: float = 0.5
    search_sigma: float = 0.25  # width of a keypoint's prior around its upright position, in person heights
    default_height_px: float = 80.0  # expected height when no map of it is given
    max_people: int = 100  # the strongest centre peaks decoded; bounds the time a noisy frame can take
    min_centre_separation: float = 0.15  # closer centre peaks (person heights) are one person's
    # A person's mask cells and box reach at most this far from the centre, in person heights (sideways, up and
    # down): a body lies within 0.2 heights of its vertical axis, and what lies beyond is a neighbour's.
    reach_sideways: float = 0.2
    reach_vertical: float = 0.6
    min_width: float = 0.25  # the narrowest box, in person heights
    side_margin: float = 0.03  # added around the keypoints and mask that set the box's width, in person heights
    # The box's top and bottom come from the person's own head and ankles (step 4) where their height lies within
    # this factor of the expected one: beyond it, one of them is a neighbour's.
    keypoint_height_range: float = 1.5
    # Keypoint peaks weaker than this are not candidates in step 2; a person left without a peak of some keypoint
    # gets it at its upright position, with the map's value there as its confidence.
    keypoint_peak_floor: float = 0.05
    # Step 1b (networks with centre offsets): the share of a person's pixels (PERSON_AREA) whose unclaimed votes
    # make one more person: low enough for a person half hidden behind another, not so low that identities switch.
    vote_support: float = 0.15
    # Step 1b's reach of a centre peak over the votes (person heights): votes this close to a peak are its person's,
    # and the free votes are gathered over windows of this radius. None: ``min_centre_separation``. Apart from the
    # peaks' separation because the two fail differently: a second peak that close is as often one person's blur,
    # while votes that close gather where a person one behind another stands.
    vote_separation: float | None = None


#: Decoder switches whose question is settled, at the value every bundle decodes with
#: (docs/decisions/0003-decoder-settings.md): a stored decode config that still names one at this value reads as
#: without it; one at the other value asks for a decoding this version does not have (:func:`stored_decode_fields`).
SETTLED_SWITCHES = {"exclusive_keypoints": True, "height_from_keypoints": True, "fine_centre_peaks": False}


class RetiredSetting(ValueError):
    """A stored config asks for what this version no longer has: ``field`` (dotted, within that config) and why.
    Readers turn it into an :class:`~vc.errors.InputError` naming their file."""

    def __init__(self, field: str, reason: str) -> None:
        self.field, self.reason = field, reason
        super().__init__(f"{field}: {reason}")


def stored_decode_fields(data: dict) -> dict:
    """A stored decode config (a bundle manifest's region ``decode``, a training config's ``decode``) as this
    version reads it: without the :data:`SETTLED_SWITCHES` it names at their settled values. A switch at the other
    value raises :class:`RetiredSetting`."""
    if not isinstance(data, dict):
        return data
    for name, settled in SETTLED_SWITCHES.items():
        if name in data and data[name] != settled:
            raise RetiredSetting(name, f"{name}={json.dumps(data[name])}, a decoding this version no longer has (it "
                                       f"decodes as {name}={json.dumps(settled)}: "
                                       f"docs/decisions/0003-decoder-settings.md)")
    return {name: value for name, value in data.items() if name not in SETTLED_SWITCHES}


@dataclass
class DecodedPerson:
    score: float
    centre: np.ndarray  # (2,) input px
    keypoints: np.ndarray  # (17, 3): x, y (input px), confidence
    box: np.ndarray  # (4,) x0, y0, x1, y1 — outer edges in input px
    mask_cells: np.ndarray  # (h, w) bool at heat-map resolution
    # The handedness maps at the centre, one per pair (:data:`vc.deploy.heatmaps.PAIRS`): > 0 where the pair's
    # image-left member is the left one (the person seen from behind), < 0 the right one (from the front); the
    # decoder ordered the pairs by their signs.
    pair_handedness: np.ndarray
    weak: bool = False  # below the centre threshold, decoded only when asked for (``decode``'s ``weak_above``)
    head_found: bool = False  # read from the head map (step 5)


def _refine_many(heatmaps: np.ndarray, rows: np.ndarray, columns: np.ndarray,
                 maps: np.ndarray | None = None) -> np.ndarray:
    """Sub-cell (x, y) of the peak at (rows[k], columns[k]) of map ``heatmaps[maps[k]]`` (``maps`` defaults to
    0, 1, 2, ...: one map per peak): the vertex of a parabola through the peak and its neighbours along each
    axis (no shift at the border, or where the values do not curve down), in float64. ``heatmaps`` may be one map
    broadcast to every peak."""
    index = np.arange(len(rows)) if maps is None else maps
    _, height, width = heatmaps.shape
    # in float64: float32 maps' largest values overflow float32's arithmetic, and the vertex would be NaN
    peak = heatmaps[index, rows, columns].astype(np.float64)

    def shift(before: np.ndarray, after: np.ndarray, inside: np.ndarray) -> np.ndarray:
        before, after = before.astype(np.float64), after.astype(np.float64)
        curvature = before - 2.0 * peak + after
        curved = inside & (curvature < 0)
        # the division only where the result is used: no warnings to silence, which costs more than the arithmetic
        # (np.minimum/np.maximum rather than np.clip, whose bound checks cost more than the arithmetic here)
        vertex = np.minimum(np.maximum(0.5 * (before - after) / np.where(curved, curvature, -1.0), -0.5), 0.5)
        return np.where(curved, vertex, 0.0)

    left, right = np.maximum(columns - 1, 0), np.minimum(columns + 1, width - 1)
    up, down = np.maximum(rows - 1, 0), np.minimum(rows + 1, height - 1)
    refined = np.empty((len(rows), 2))
    refined[:, 0] = columns + shift(heatmaps[index, rows, left], heatmaps[index, rows, right],
                                    (columns > 0) & (columns < width - 1))
    refined[:, 1] = rows + shift(heatmaps[index, up, columns], heatmaps[index, down, columns],
                                 (rows > 0) & (rows < height - 1))
    return refined


#: The tallest expected person height the decoders accept, in network-input pixels (the C decoder's
#: VC_MAX_HEIGHT_PX): beyond it a region's camera model is broken.
MAX_EXPECTED_HEIGHT_PX = 100_000.0


def check_decodable(heatmaps: np.ndarray, expected_height_px: np.ndarray | None) -> None:
    """Refuses (ValueError) heat maps (C, h, w) in none of the :data:`~vc.deploy.heatmaps.LAYOUTS`, or holding NaN
    or infinite values (a network emitting them is broken: nothing read from them would mean anything), and
    expected heights that are not finite and within (0, :data:`MAX_EXPECTED_HEIGHT_PX`] or not one per heat-map
    cell. The C decoder refuses the same (:mod:`vc.deploy.native`)."""
    channels = heatmaps.shape[0]
    if channels == ANATOMICAL_CHANNELS:
        raise ValueError(f"heat maps have {channels} channels, the layout of networks from before the handedness "
                         f"maps, which this version does not decode (docs/decisions/0003-decoder-settings.md)")
    if channels not in LAYOUTS:
        raise ValueError(f"heat maps have {channels} channels; a ScenePoseNet emits one of the layouts {LAYOUTS}")
    if not np.isfinite(heatmaps).all():
        raise ValueError("heat maps hold NaN or infinite values")
    if expected_height_px is not None:
        if expected_height_px.shape != heatmaps.shape[1:]:
            raise ValueError(f"expected heights of shape {expected_height_px.shape} for heat maps of "
                             f"{heatmaps.shape[1:]}")
        if not ((expected_height_px > 0) & (expected_height_px <= MAX_EXPECTED_HEIGHT_PX)).all():
            raise ValueError(f"expected heights must be finite and within (0, {MAX_EXPECTED_HEIGHT_PX:g}] px")


def find_peaks(heatmap: np.ndarray, threshold: float, limit: int | None = None) -> list[tuple[float, np.ndarray]]:
    """(value, (x, y) in cells) of the (at most ``limit`` strongest) local maxima above ``threshold``, strongest
    first (:func:`local_maxima` of one map)."""
    _, values, positions = local_maxima(heatmap[None], threshold, limit)
    return list(zip(values.tolist(), positions, strict=True))


def local_maxima(maps: np.ndarray, threshold: float, limit: int | None = None,
                 windows: list[tuple[int, int, int, int]] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The local maxima above ``threshold`` of each of ``maps`` (C, h, w), all maps at once: their map (K,),
    value (K,) and sub-cell (x, y) (K, 2), ordered by map and, within a map, strongest first; at most ``limit``
    a map. ``windows`` (row start, row stop, column start, column stop; not overlapping): only the peaks inside
    them, each judged against its neighbours in the whole map — the peaks a search of the whole map finds there;
    ``limit`` then counts the windows' peaks only.

    A peak is at least as high as its 8 neighbours and strictly higher than the 4 that come before it in
    reading order, so a plateau of equal values yields its first cell only.
    """
    _, height, width = maps.shape
    windows = [(0, height, 0, width)] if windows is None else windows
    found, rows, columns, values = (
        (np.concatenate(parts) for parts in zip(*(_maxima_in(maps, threshold, window) for window in windows),
                                                strict=True))
        if windows else (np.zeros(0, int), np.zeros(0, int), np.zeros(0, int), np.zeros(0, maps.dtype)))
    order = np.lexsort((-values, found))  # stable: equal values keep reading order
    found, rows, columns, values = found[order], rows[order], columns[order], values[order]
    if limit is not None:
        first_of_map = np.searchsorted(found, found)  # the index where each peak's map begins
        within = np.arange(len(found)) - first_of_map < limit
        found, rows, columns, values = found[within], rows[within], columns[within], values[within]
    return found, values, _refine_many(maps, rows, columns, found)


def _maxima_in(maps: np.ndarray, threshold: float,
               window: tuple[int, int, int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The map, row, column and value of each local maximum (:func:`local_maxima`) inside ``window``, in map then
    reading order."""
    channels, height, width = maps.shape
    top, bottom, left, right = window
    rows_inside, columns_inside = bottom - top, right - left
    # The window and a ring of one cell around it, -inf beyond the map's border (np.pad's generality costs more).
    padded = np.full((channels, rows_inside + 2, columns_inside + 2), -np.inf, maps.dtype)
    padded[:, max(1 - top, 0):rows_inside + 2 - max(bottom + 1 - height, 0),
           max(1 - left, 0):columns_inside + 2 - max(right + 1 - width, 0)] = \
        maps[:, max(top - 1, 0):min(bottom + 1, height), max(left - 1, 0):min(right + 1, width)]
    # Only the cells above the threshold are compared with their neighbours (a few percent of a map's cells: a
    # tenth of the time of comparing whole maps), one pair of opposite neighbours at a time, the cells that fail
    # dropped before the next pair is read (on PETS09's keypoint maps two thirds fail the first pair).
    inside = np.zeros(padded.shape, bool)
    inside[:, 1:-1, 1:-1] = padded[:, 1:-1, 1:-1] > threshold
    at = np.flatnonzero(inside)  # in reading order of the padded maps
    flat = padded.reshape(-1)
    values = flat[at]
    row_length = columns_inside + 2
    for step in (1, row_length, row_length + 1, row_length - 1):  # strictly above the neighbour before in reading
        higher = (values > flat[at - step]) & (values >= flat[at + step])  # order: ties go to the first cell
        at, values = at[higher], values[higher]
    found, cell = np.divmod(at, (rows_inside + 2) * row_length)
    rows, columns = np.divmod(cell, row_length)
    return found, rows - 1 + top, columns - 1 + left, values


def decode(heatmaps: np.ndarray, config: DecodeConfig = DecodeConfig(),
           expected_height_px: np.ndarray | None = None, weak_above: float | None = None,
           prior: UprightPrior = UPRIGHT_PRIOR) -> list[DecodedPerson]:
    """People in one sample's heat maps (C, h, w), C one of the :data:`~vc.deploy.heatmaps.LAYOUTS`: with or
    without centre offsets, with or without the fine centre map (which it does not read), with or without the head
    and size maps (step 5, every person of the first reading kept).
    ``expected_height_px`` (h, w): the pixel height of a person whose centre is at each cell, from the region's
    camera; None falls back to ``config.default_height_px``.

    ``weak_above`` (below ``config.centre_threshold``): the centre peaks down to it are decoded too, as ``weak``
    people (for a tracker: :mod:`vc.deploy.tracking`). They take no mask cells or keypoint peaks from the others,
    which come out as they would without them."""
    readings = decode_readings(heatmaps, config, expected_height_px, weak_above, prior)
    return one_head_each(with_heads_added(readings, config.max_people))


def decode_readings(heatmaps: np.ndarray, config: DecodeConfig = DecodeConfig(),
                    expected_height_px: np.ndarray | None = None, weak_above: float | None = None,
                    prior: UprightPrior = UPRIGHT_PRIOR) -> list[DecodedPerson]:
    """:func:`decode`'s people before step 5's rules: the first reading's, then (from a network with a head map)
    every strong person read from the heads, flagged ``head_found``. Which of these step 5 adds depends on which of
    the first reading a caller keeps (a region keeps the people standing in its owned area,
    :mod:`vc.deploy.runtime`): :func:`with_heads_added`, then :func:`one_head_each` over what is reported."""
    check_decodable(heatmaps, expected_height_px)
    people = _read(heatmaps, config, expected_height_px, weak_above, prior, from_heads=False)
    if heatmaps.shape[0] == HEAD_CHANNELS:
        people += [replace(person, head_found=True)
                   for person in _read(heatmaps, config, expected_height_px, weak_above, prior, from_heads=True)
                   if not person.weak]
    return people


def with_heads_added(people: list, max_people: int) -> list:
    """Step 5's union over ``people`` (:func:`decode_readings`' or the runtime's, anything with ``box``, ``weak``
    and ``head_found``): those of the first reading, and those read from the heads whose box overlaps every strong
    one of the first by less than :data:`HEAD_UNION_IOU`, at most ``max_people`` in all."""
    first = [person for person in people if not person.head_found]
    boxes = np.array([person.box for person in first if not person.weak]).reshape(-1, 4)
    added = [person for person in people if person.head_found
             and (not len(boxes) or box_iou(person.box[None], boxes).max() < HEAD_UNION_IOU)]
    return first + added[:max(max_people - len(first), 0)]


def one_head_each(people: list, reach: float = SAME_HEAD_REACH) -> list:
    """``people`` (anything with ``box``, ``weak`` and ``head_found``) without those read from the heads whose head
    (their box's top middle) lies within ``reach`` of another strong person's height of that person's head,
    strictly: one head, one person. Weak people (a tracker's) neither count nor go."""
    if not any(person.head_found for person in people):
        return people
    strong = [person for person in people if not person.weak]
    boxes = np.array([person.box for person in strong], np.float64).reshape(-1, 4)
    heads = np.column_stack([(boxes[:, 0] + boxes[:, 2]) / 2, boxes[:, 1]])
    distances = np.hypot(heads[:, None, 0] - heads[None, :, 0], heads[:, None, 1] - heads[None, :, 1])  # (N, N)
    near = distances < reach * (boxes[:, 3] - boxes[:, 1])[None]  # [i, j]: i's head within reach of j's height
    np.fill_diagonal(near, False)
    dropped = {id(person) for person, again in zip(strong, near.any(axis=1), strict=True)
               if again and person.head_found}
    return [person for person in people if id(person) not in dropped]


def _read(heatmaps: np.ndarray, config: DecodeConfig, expected_height_px: np.ndarray | None,
          weak_above: float | None, prior: UprightPrior, from_heads: bool) -> list[DecodedPerson]:
    """Steps 1-4 on the centre map's peaks, or (``from_heads``, step 5) on the head map's."""
    stride = config.stride
    channels, height, width = heatmaps.shape

    def heights_px_at(xy_cells: np.ndarray) -> np.ndarray:
        if expected_height_px is None:
            return np.full(len(xy_cells), config.default_height_px)
        rows = np.minimum(np.maximum(np.round(xy_cells[:, 1]).astype(int), 0), height - 1)
        columns = np.minimum(np.maximum(np.round(xy_cells[:, 0]).astype(int), 0), width - 1)
        return expected_height_px[rows, columns].astype(float)

    # a Python float: numpy compares float32 maps with it in float32 (as the C decoder does), with a numpy scalar
    # in float64
    floor = float(config.centre_threshold if weak_above is None else min(weak_above, config.centre_threshold))
    centre_map = heatmaps[HEAD_CHANNEL if from_heads else CENTRE_CHANNEL]
    peaks = find_peaks(centre_map, floor, config.max_people)

    def centre_value_at(centre_cells: np.ndarray) -> float:
        column, row = np.clip(np.round(centre_cells).astype(int), 0, [width - 1, height - 1])
        return float(centre_map[row, column])

    centres_cells = np.array([centre for _, centre in peaks]).reshape(-1, 2)
    if from_heads:  # heads stand apart: none is merged; each is moved to its person's centre
        centres_cells, sized_cells = _centres_from_heads(heatmaps, centres_cells, stride)
        peaks = [(score, centre) for (score, _), centre in zip(peaks, centres_cells, strict=True)]
    else:
        keep = _separated(centres_cells, heights_px_at(centres_cells) / stride, config.min_centre_separation)
        peaks, centres_cells = [peaks[i] for i in keep], centres_cells[keep]
        sized_cells = np.full(len(peaks), np.nan)

    mask = heatmaps[MASK_CHANNEL]
    mask_rows, mask_columns = np.nonzero(mask > config.mask_threshold)
    # Where each foreground cell says its person's centre is (step 1b); without offsets, the cell itself.
    voted = np.column_stack([mask_columns, mask_rows]).astype(np.float64)
    if channels >= OFFSET_CHANNELS and len(voted):
        offsets = heatmaps[CENTRE_OFFSET_CHANNELS][:, mask_rows, mask_columns].T  # (M, 2) in person heights
        scale = (_size_cells(heatmaps, mask_rows, mask_columns, stride) if from_heads
                 else heights_px_at(voted) / stride)
        voted += offsets * scale[:, None]
        moved, added = _vote_centres(voted, mask[mask_rows, mask_columns], heights_px_at(voted) / stride,
                                     (height, width), centres_cells, heights_px_at(centres_cells) / stride, config)
        for index, centre in moved.items():
            peaks[index], centres_cells[index] = (peaks[index][0], centre), centre
            sized_cells[index] = np.nan  # the votes' person: the decoder's box
        for centre in added:
            score = centre_value_at(centre)
            if score >= floor and len(peaks) < config.max_people:
                peaks.append((score, centre))
                centres_cells = np.vstack([centres_cells, centre])
                sized_cells = np.append(sized_cells, np.nan)
    if not peaks:
        return []
    heights_px = heights_px_at(centres_cells)
    heights_cells = heights_px / stride

    strong = np.array([score >= config.centre_threshold for score, _ in peaks])

    # Mask cells go to the centre nearest their vote, distance measured in expected heights (a strong person's, to
    # the nearest strong centre: weak people take nothing from them). Only foreground cells are owned, so only they
    # are measured: a frame's people cover a small part of it.
    scaled = np.hypot(voted[None, :, 0] - centres_cells[:, 0, None],
                      voted[None, :, 1] - centres_cells[:, 1, None]) / heights_cells[:, None]  # (N, foreground cells)
    owner = np.argmin(scaled, axis=0)
    strong_indices = np.flatnonzero(strong)
    owner_among_strong = strong_indices[np.argmin(scaled[strong_indices], axis=0)] if len(strong_indices) else owner

    keypoint_maps = heatmaps[KEYPOINT_CHANNELS]
    # Strong people share out the keypoint peaks (step 2); weak ones search their own, taking nothing from them.
    shared_out = dict(zip(strong_indices, _exclusive_keypoints(keypoint_maps, centres_cells[strong],
                                                               heights_cells[strong], config, prior), strict=True))
    searched = [index for index in range(len(peaks)) if index not in shared_out]
    own_keypoints = dict(zip(searched, _keypoints(keypoint_maps, centres_cells[searched], heights_cells[searched],
                                                  config, prior), strict=True))
    keypoints = np.stack([shared_out[index] if index in shared_out else own_keypoints[index]
                          for index in range(len(peaks))])  # (N, 17, 3)
    centre_rows, centre_columns = (np.round(centres_cells[:, ::-1]).astype(int)).T
    pair_handedness = heatmaps[HANDEDNESS_CHANNELS][:, centre_rows, centre_columns].T  # (N, pairs)
    # A negative handedness: the pair's image-left member is the person's right one.
    keypoints = swap_pairs(keypoints, pair_handedness < 0)
    within_reach = ((np.abs(mask_columns[None] - centres_cells[:, 0, None])
                     <= config.reach_sideways * heights_cells[:, None])
                    & (np.abs(mask_rows[None] - centres_cells[:, 1, None])
                       <= config.reach_vertical * heights_cells[:, None]))  # (N, foreground cells)
    owned = (np.where(strong[:, None], owner_among_strong[None], owner[None])
             == np.arange(len(peaks))[:, None]) & within_reach
    centres = cells_to_input(centres_cells, stride)
    boxes = _boxes(centres, heights_px, keypoints, owned, mask_columns, config, prior)
    # step 5: the size map's height, centred on the centre, where step 4's disagrees with it (NaN: the decoder's box)
    ratio = (boxes[:, 3] - boxes[:, 1]) / (sized_cells * stride)
    sized = np.isfinite(sized_cells) & ~((ratio >= 1.0 / HEAD_HEIGHT_AGREEMENT) & (ratio <= HEAD_HEIGHT_AGREEMENT))
    boxes[sized, 1] = centres[sized, 1] - sized_cells[sized] * stride / 2
    boxes[sized, 3] = centres[sized, 1] + sized_cells[sized] * stride / 2
    people = []
    for index, (score, _) in enumerate(peaks):
        mask_cells = np.zeros((height, width), bool)
        mask_cells[mask_rows[owned[index]], mask_columns[owned[index]]] = True
        people.append(DecodedPerson(score=score, centre=centres[index], keypoints=keypoints[index], box=boxes[index],
                                    mask_cells=mask_cells, pair_handedness=pair_handedness[index],
                                    weak=not strong[index]))
    return people


def _size_cells(heatmaps: np.ndarray, rows: np.ndarray, columns: np.ndarray, stride: int) -> np.ndarray:
    """The size map's person heights (cells) at these cells, at most :data:`MAX_EXPECTED_HEIGHT_PX` (a taller one is
    as broken as a camera model giving it, and would overflow)."""
    largest = math.log(MAX_EXPECTED_HEIGHT_PX / stride / SIZE_UNIT_CELLS)  # libm's log, as the C decoder's
    return SIZE_UNIT_CELLS * np.exp(np.minimum(heatmaps[SIZE_CHANNEL, rows, columns].astype(np.float64), largest))


def _centres_from_heads(heatmaps: np.ndarray, heads_cells: np.ndarray, stride: int) -> tuple[np.ndarray, np.ndarray]:
    """Step 5: the centres (cells) of the people whose heads are at ``heads_cells`` (N, 2), the head plus the centre
    offset at its cell times the size map's height there, kept on the map; and those heights (N,)."""
    _, height, width = heatmaps.shape
    rows = np.minimum(np.maximum(np.round(heads_cells[:, 1]).astype(int), 0), height - 1)
    columns = np.minimum(np.maximum(np.round(heads_cells[:, 0]).astype(int), 0), width - 1)
    sizes = _size_cells(heatmaps, rows, columns, stride)
    offsets = heatmaps[CENTRE_OFFSET_CHANNELS][:, rows, columns].T.astype(np.float64)  # (N, 2) person heights
    centres = heads_cells + offsets * sizes[:, None]
    centres[:, 0] = np.minimum(np.maximum(centres[:, 0], 0.0), width - 1)
    centres[:, 1] = np.minimum(np.maximum(centres[:, 1], 0.0), height - 1)
    return centres, sizes


def _keypoints(keypoint_maps: np.ndarray, centres_cells: np.ndarray, heights_cells: np.ndarray,
               config: DecodeConfig, prior: UprightPrior = UPRIGHT_PRIOR) -> np.ndarray:
    """(N, 17, 3) keypoints of the N people at ``centres_cells``: each the maximum of its map times the person's
    upright prior (weak people's, step 2).

    A person's search covers the cells within 3 prior widths of the expected position (beyond that the prior is
    below 1 %), which keeps their cost independent of the region's size. All people are searched at once, in
    windows of one size (the largest person's, moved inside the map where it would stick out) with the cells
    outside each person's own window left out: the first maximum in reading order is the one a search of their
    own window finds.
    """
    count = len(centres_cells)
    channels, height, width = keypoint_maps.shape
    keypoints = np.zeros((count, channels, 3))
    if not count:
        return keypoints
    sigmas = config.search_sigma * np.asarray(heights_cells, np.float64)  # (N,)
    reaches = np.ceil(3.0 * sigmas).astype(int)
    centre_columns = np.round(centres_cells[:, 0]).astype(int)
    x0 = np.maximum(centre_columns - reaches, 0)
    x1 = np.minimum(centre_columns + reaches + 1, width)
    expected_rows = centres_cells[:, 1, None] + prior.offsets[None, :channels] * heights_cells[:, None]  # (N, 17)
    starts = np.maximum(np.round(expected_rows).astype(int) - reaches[:, None], 0)
    stops = np.minimum(np.round(expected_rows).astype(int) + reaches[:, None] + 1, height)
    # A keypoint whose expected position is far off the map is not looked for.
    seen = (starts < stops) & (x0 < x1)[:, None]
    if not seen.any():
        return keypoints
    y0 = np.where(seen, starts, height).min(axis=1)
    y1 = np.where(seen, stops, 0).max(axis=1)
    window_height = int(np.max(y1 - y0, initial=1))
    window_width = int(np.max(x1 - x0, initial=1))
    top = np.minimum(np.maximum(y0, 0), height - window_height)  # where each person's window starts (N,)
    left = np.minimum(np.maximum(x0, 0), width - window_width)
    rows = top[:, None] + np.arange(window_height)  # (N, R)
    columns = left[:, None] + np.arange(window_width)  # (N, C)
    prior_x = np.exp(-(columns - centres_cells[:, 0, None]) ** 2 / (2.0 * sigmas[:, None] ** 2))  # (N, C)
    prior_y = np.exp(-(rows[:, None, :] - expected_rows[:, :, None]) ** 2
                     / (2.0 * sigmas[:, None, None] ** 2))  # (N, 17, R)
    in_window = (rows[:, None, :] >= starts[:, :, None]) & (rows[:, None, :] < stops[:, :, None])  # (N, 17, R)
    in_columns = (columns >= x0[:, None]) & (columns < x1[:, None])  # (N, C)
    windows = np.lib.stride_tricks.sliding_window_view(keypoint_maps, (window_height, window_width), axis=(1, 2))
    window = windows[:, top, left].transpose(1, 0, 2, 3)  # (N, 17, R, C)
    usable = in_window[..., None] & in_columns[:, None, None, :]
    weighted = np.where(usable, window * (prior_y[..., None] * prior_x[:, None, None, :]), -np.inf)
    best = weighted.reshape(count, channels, -1).argmax(axis=2)  # (N, 17)
    people, keypoint_channels = np.nonzero(seen)
    best = best[people, keypoint_channels]
    peak_rows = top[people] + best // window_width
    peak_columns = left[people] + best % window_width
    keypoints[people, keypoint_channels, :2] = cells_to_input(
        _refine_many(keypoint_maps, peak_rows, peak_columns, keypoint_channels), config.stride)
    keypoints[people, keypoint_channels, 2] = keypoint_maps[keypoint_channels, peak_rows, peak_columns]
    return keypoints


def _exclusive_keypoints(keypoint_maps: np.ndarray, centres_cells: np.ndarray, heights_cells: np.ndarray,
                         config: DecodeConfig, prior: UprightPrior = UPRIGHT_PRIOR) -> np.ndarray:
    """(N, 17, 3) keypoints of the N people at ``centres_cells`` with each keypoint peak given to one person at
    most (step 2): per keypoint map, every (person, peak) pair is scored by the peak's value times the person's
    upright prior (as in :func:`_keypoints`, cut at 3 prior widths), and pairs are taken best first while both
    are free. A person who gets no peak has the keypoint at its upright position, with the map's value there."""
    count, channels = len(centres_cells), keypoint_maps.shape[0]
    _, height, width = keypoint_maps.shape
    sigmas = config.search_sigma * heights_cells  # (N,)
    expected = np.empty((count, channels, 2))  # (N, 17, 2) cells
    expected[..., 0] = centres_cells[:, 0, None]
    expected[..., 1] = centres_cells[:, 1, None] + prior.offsets[None, :channels] * heights_cells[:, None]
    on_map = (expected[..., 1] > -0.5) & (expected[..., 1] < height - 0.5)  # (N, 17)
    # Every map's peaks at once (K in all), scored against every person: the maps do not compete, so taking the
    # pairs best first over all of them takes each map's best first (equal scores in (person, peak) order).
    reach = 3.0 * sigmas  # a peak further from a keypoint's expected position is not that person's
    peak_maps, values, positions = local_maxima(keypoint_maps, config.keypoint_peak_floor, 4 * count + 8,
                                                _search_windows(expected, reach, (height, width)))
    offset = positions[None] - expected[:, peak_maps]  # (N, K, 2)
    near = (np.abs(offset) <= reach[:, None, None]).all(-1) & on_map[:, peak_maps]
    scores = np.where(near, values[None] * np.exp(-(offset**2).sum(-1) / (2.0 * sigmas[:, None] ** 2)), 0.0)
    candidates = np.flatnonzero(scores > 0.0)
    # (Python sets and lists: the loop reads one element at a time, which numpy arrays make slow.)
    slots_taken: set[tuple[int, int]] = set()
    peaks_taken: set[int] = set()
    owners, owned = [], []
    people_of, peaks_of = np.divmod(candidates[np.argsort(-scores.ravel()[candidates], kind="stable")], len(values))
    for person, peak, peak_map in zip(people_of.tolist(), peaks_of.tolist(), peak_maps[peaks_of].tolist(),
                                      strict=True):
        slot = (person, peak_map)
        if slot in slots_taken or peak in peaks_taken:
            continue
        slots_taken.add(slot)
        peaks_taken.add(peak)
        owners.append(person)
        owned.append(peak)
    keypoints = np.zeros((count, channels, 3))
    owners, owned = np.array(owners, int), np.array(owned, int)
    taken = np.zeros((count, channels), bool)
    taken[owners, peak_maps[owned]] = True
    keypoints[owners, peak_maps[owned], :2] = cells_to_input(positions[owned], config.stride)
    keypoints[owners, peak_maps[owned], 2] = values[owned]
    people, lacking = np.nonzero(~taken & on_map)
    keypoints[people, lacking, :2] = cells_to_input(expected[people, lacking], config.stride)
    nearest = np.minimum(np.maximum(np.round(expected[people, lacking]).astype(int), 0),
                         [width - 1, height - 1])  # (x, y) cells
    keypoints[people, lacking, 2] = keypoint_maps[lacking, nearest[:, 1], nearest[:, 0]]
    return keypoints


def _search_windows(expected: np.ndarray, reach: np.ndarray,
                    shape: tuple[int, int]) -> list[tuple[int, int, int, int]]:
    """Rectangles of cells (row start, row stop, column start, column stop) holding every cell whose peak can lie
    within ``reach`` (N,) of one of the N people's ``expected`` keypoint positions (N, 17, 2), not overlapping:
    the people's column spans merged where they meet, each with the rows of its people. A frame's people cover
    a small part of it (PETS09's far region: one person in 188 columns), so their keypoints are searched there
    only."""
    height, width = shape
    margin = reach + 0.5  # a peak's sub-cell position lies within half a cell of its cell
    # (np.minimum/np.maximum rather than np.clip, as in _refine_many)
    starts = np.minimum(np.maximum(np.floor(expected[:, 0, 0] - margin).astype(int), 0), width)
    stops = np.minimum(np.maximum(np.ceil(expected[:, 0, 0] + margin).astype(int) + 1, 0), width)
    tops = np.minimum(np.maximum(np.floor(expected[..., 1].min(axis=1) - margin).astype(int), 0), height)
    bottoms = np.minimum(np.maximum(np.ceil(expected[..., 1].max(axis=1) + margin).astype(int) + 1, 0), height)
    windows: list[tuple[int, int, int, int]] = []
    for person in np.argsort(starts, kind="stable").tolist():
        if starts[person] >= stops[person] or tops[person] >= bottoms[person]:
            continue
        if windows and starts[person] <= windows[-1][3]:  # meets the last span: one window
            top, bottom, left, right = windows[-1]
            windows[-1] = (min(top, tops[person]), max(bottom, bottoms[person]), left, max(right, stops[person]))
        else:
            windows.append((int(tops[person]), int(bottoms[person]), int(starts[person]), int(stops[person])))
    return windows


def _vote_centres(voted: np.ndarray, weights: np.ndarray, vote_heights: np.ndarray, shape: tuple[int, int],
                  peaks: np.ndarray, peak_heights: np.ndarray,
                  config: DecodeConfig) -> tuple[dict[int, np.ndarray], list[np.ndarray]]:
    """Step 1b: where the pixels' votes put people that the centre peaks miss. ``voted`` (M, 2) are the voted
    centres of the foreground cells, ``weights`` their mask values, ``vote_heights`` the expected height (cells) at
    each vote, ``shape`` the map's; ``peaks`` (N, 2) the centre peaks, ``peak_heights`` theirs.

    Votes within ``vote_separation`` heights of a peak are that peak's. The rest are summed on the map, each
    as its share of one person's pixels (:data:`PERSON_AREA`), over windows of that separation (at the votes' median
    height): the heaviest window, if it holds at least ``vote_support`` of a person, is a person at its votes'
    weighted mean; its votes leave the map, and the next heaviest is weighed, at most ``max_people`` times
    (a summed-area table gives every window's sum at once, however many votes there are; after each round only
    the windows that overlap the one emptied are summed again: a crowd's twenty rounds cost about one).

    A peak that few pixels vote for (less than ``vote_support``), within :data:`MERGED_PEAK_REACH` of such a
    person, is the blur of people around it: it moves to the first of them (keeping its score), and the others are
    added. Returns the moved peaks (index -> centre) and the added centres, in cells.
    """
    height, width = shape
    share = weights / (PERSON_AREA * vote_heights**2)  # each vote's share of one person's pixels
    distances = np.hypot(voted[:, None, 0] - peaks[None, :, 0], voted[:, None, 1] - peaks[None, :, 1])  # (M, N)
    separation = config.min_centre_separation if config.vote_separation is None else config.vote_separation
    claims = distances <= separation * peak_heights[None]
    unsupported = _ordered_sum(np.where(claims, share[:, None], 0.0)) < config.vote_support  # (N,): peaks that
    # few pixels vote for
    cells = np.round(voted).astype(int)
    free = ~claims.any(axis=1) & (cells[:, 0] >= 0) & (cells[:, 0] < width) & (cells[:, 1] >= 0) & (
        cells[:, 1] < height)
    moved: dict[int, np.ndarray] = {}
    added: list[np.ndarray] = []
    if not free.any():
        return moved, added
    # (a window wider than the map sums what one as wide as the map sums: the radius stops there)
    radius = min(max(1, int(round(separation * _median(vote_heights[free])))), max(height, width))
    votes_map = np.zeros(shape)
    np.add.at(votes_map, (cells[free, 1], cells[free, 0]), share[free])
    support = _window_sums(votes_map, radius)
    for _ in range(config.max_people):
        row, column = np.unravel_index(int(np.argmax(support)), shape)
        if support[row, column] < config.vote_support:
            break
        members = free & (np.abs(cells[:, 0] - column) <= radius) & (np.abs(cells[:, 1] - row) <= radius)
        weights = share[members, None]  # np.average's arithmetic, summed in order
        centre = _ordered_sum(np.multiply(voted[members], weights)) / _ordered_sum(weights)
        np.add.at(votes_map, (cells[members, 1], cells[members, 0]), -share[members])
        _update_window_sums(support, votes_map, radius, row, column)
        free &= ~members
        reach = np.hypot(*(peaks - centre).T) / peak_heights  # (N,) in heights
        blurs = np.flatnonzero(unsupported & (reach <= MERGED_PEAK_REACH))
        blurs = [index for index in blurs[np.argsort(reach[blurs], kind="stable")] if index not in moved]
        if blurs:
            moved[blurs[0]] = centre
        else:
            added.append(centre)
    return moved, added


def _ordered_sum(values: np.ndarray) -> np.ndarray:
    """The sum over the first axis, adding in index order: numpy's own sum adds pairwise or in whatever order its
    loops run, a rounding another implementation cannot follow (the C decoder, :mod:`vc.deploy.native`, adds in
    order), and these sums decide who is a person."""
    return np.cumsum(values, axis=0)[-1] if len(values) else np.zeros(values.shape[1:])


def _median(values: np.ndarray) -> float:
    """``np.median`` of a 1-D array, without its generality's cost (a tenth of the decoder's vote step)."""
    ordered = np.sort(values)
    middle = len(ordered) // 2
    return float(ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2)


def _window_sums(grid: np.ndarray, radius: int) -> np.ndarray:
    """The sum of ``grid`` over the (2 radius + 1)^2 window around each cell (zeros beyond the border), from a
    summed-area table. Along an axis the radius stops at the grid's extent, beyond which it changes no sum (not
    one bit: the table's sums beyond the grid are its last ones)."""
    height, width = grid.shape
    row_radius, column_radius = min(radius, height), min(radius, width)
    row_side, column_side = 2 * row_radius + 1, 2 * column_radius + 1
    table = np.zeros((height + row_side, width + column_side))  # a zero row and column, then the padded grid
    table[row_radius + 1:row_radius + 1 + height, column_radius + 1:column_radius + 1 + width] = grid  # (np.pad's
    table.cumsum(axis=0, out=table)                              # generality costs more than the sums, every round)
    table.cumsum(axis=1, out=table)
    return (table[row_side:, column_side:] - table[:-row_side, column_side:] - table[row_side:, :-column_side]
            + table[:-row_side, :-column_side])


def _update_window_sums(sums: np.ndarray, grid: np.ndarray, radius: int, row: int, column: int) -> None:
    """``sums`` (:func:`_window_sums` of ``grid`` before the cells within ``radius`` of (row, column) changed)
    brought up to date: only the windows within two radii of that cell hold a changed cell, and each of them reads
    the grid at most one radius further out."""
    height, width = grid.shape
    rows = slice(max(0, row - 2 * radius), min(height, row + 2 * radius + 1))
    columns = slice(max(0, column - 2 * radius), min(width, column + 2 * radius + 1))
    read_rows = slice(max(0, rows.start - radius), min(height, rows.stop + radius))
    read_columns = slice(max(0, columns.start - radius), min(width, columns.stop + radius))
    # Zeros beyond the read slice are right: it ends one radius past the updated windows, or at the grid's border.
    local = _window_sums(grid[read_rows, read_columns], radius)
    sums[rows, columns] = local[rows.start - read_rows.start:rows.stop - read_rows.start,
                                columns.start - read_columns.start:columns.stop - read_columns.start]


def _separated(centres_cells: np.ndarray, heights_cells: np.ndarray, separation: float) -> list[int]:
    """Indices of the peaks (strongest first) that lie at least ``separation`` expected heights from every
    stronger peak kept: two centres closer than that are one person's blurred peak, not two people."""
    # apart[i, j]: peak i is far enough from peak j, in j's expected heights (all pairs at once; the greedy pass
    # over them is then plain Python on a handful of peaks)
    apart = (np.hypot(*(centres_cells[:, None] - centres_cells[None]).transpose(2, 0, 1))
             >= separation * heights_cells[None]).tolist()
    kept: list[int] = []
    for index, row in enumerate(apart):
        if all(row[other] for other in kept):
            kept.append(index)
    return kept


#: Head keypoints (nose, eyes, ears) and ankles: the top and the bottom of a person's keypoints.
HEAD_KEYPOINTS = np.array([COCO_KEYPOINTS.index(name) for name in
                           ("nose", "left_eye", "right_eye", "left_ear", "right_ear")])
ANKLE_KEYPOINTS = np.array([COCO_KEYPOINTS.index(name) for name in ("left_ankle", "right_ankle")])


def _boxes(centres: np.ndarray, heights_px: np.ndarray, keypoints: np.ndarray, owned: np.ndarray,
           mask_columns: np.ndarray, config: DecodeConfig, prior: UprightPrior = UPRIGHT_PRIOR) -> np.ndarray:
    """(N, 4) boxes of the N people at ``centres`` (input px) with expected ``heights_px``, ``keypoints`` (N, 17, 3)
    and ``owned`` (N, M) of the M foreground cells in ``mask_columns`` (see module docstring, step 4; all people at
    once). Top and bottom from the highest confident head keypoint and the lowest confident ankle: on the upright
    prior they lie ``offset`` person heights from the centre, so their distance is the height times the difference
    of their offsets, and the head's top and the soles lie half a height from the centre; without both, and where
    that height is more than ``keypoint_height_range`` times off the expected one (a neighbour's ankle), the
    expected height centred on the centre. The width spans the confident keypoints and the mask cells within reach
    sideways, plus a margin, and is at least ``min_width``."""
    count = len(centres)
    x, y = keypoints[..., 0], keypoints[..., 1]
    confident = keypoints[..., 2] >= config.keypoint_threshold  # (N, 17)
    spanning = confident & (np.abs(x - centres[:, 0, None]) <= config.reach_sideways * heights_px[:, None])
    lowest = np.where(spanning, x, np.inf).min(axis=1)
    highest = np.where(spanning, x, -np.inf).max(axis=1)
    has_mask = owned.any(axis=1)
    if has_mask.any():
        first_column = np.where(owned, mask_columns[None], np.iinfo(np.int64).max).min(axis=1)
        last_column = np.where(owned, mask_columns[None], -1).max(axis=1)
        lowest = np.where(has_mask, np.minimum(lowest, cells_to_input(first_column - 0.5, config.stride)), lowest)
        highest = np.where(has_mask, np.maximum(highest, cells_to_input(last_column + 0.5, config.stride)), highest)
    spanned = np.isfinite(lowest)  # without keypoints or mask the box is the narrowest one around the centre
    lowest, highest = np.where(spanned, lowest, centres[:, 0]), np.where(spanned, highest, centres[:, 0])
    margin, half_min = config.side_margin * heights_px, config.min_width * heights_px / 2
    left = np.maximum(centres[:, 0] - lowest + margin, half_min)
    right = np.maximum(highest - centres[:, 0] + margin, half_min)

    top, bottom = centres[:, 1] - heights_px / 2, centres[:, 1] + heights_px / 2
    heads = confident[:, HEAD_KEYPOINTS]
    ankles = confident[:, ANKLE_KEYPOINTS]
    both = heads.any(axis=1) & ankles.any(axis=1)
    head = HEAD_KEYPOINTS[np.argmin(np.where(heads, y[:, HEAD_KEYPOINTS], np.inf), axis=1)]
    ankle = ANKLE_KEYPOINTS[np.argmax(np.where(ankles, y[:, ANKLE_KEYPOINTS], -np.inf), axis=1)]
    people = np.arange(count)
    head_y, ankle_y = y[people, head], y[people, ankle]
    height = (ankle_y - head_y) / (prior.lower_ankle - prior.offsets[head])
    ratio = height / heights_px
    from_keypoints = both & (1.0 / config.keypoint_height_range <= ratio) & (ratio <= config.keypoint_height_range)
    keypoint_top = head_y - (0.5 + prior.offsets[head]) * height
    top = np.where(from_keypoints, keypoint_top, top)
    bottom = np.where(from_keypoints, keypoint_top + height, bottom)
    return np.stack([centres[:, 0] - left, top, centres[:, 0] + right, bottom], axis=1)
