"""Running a bundle on full frames: numpy and onnxruntime only (an appliance has nothing else; OpenVINO where asked).

Per frame: cut each region's crop window (the graph resizes and normalises it), run the region models, decode
their heat maps (:mod:`vc.deploy.decode`, the same code the training evaluation uses), keep the people each region
owns — those whose foot point falls in its owned image area — and map them to frame pixels. At a seam between two
regions the foot point is uncertain by a few pixels (it is the bottom of a decoded box), so a region also keeps a
person whose feet it puts just across the seam, in a neighbour's area within :data:`SEAM_FOOT_TOLERANCE` box
heights of its own: otherwise a person the neighbour does not find is lost by both. A person standing on the seam
can so be kept twice, once by each region (PETS09 frame 1: one walker's feet at y 319 in r1 and 323 in r2, boxes
at IoU 0.88). Of two people of different regions overlapping more than :data:`SEAM_DUPLICATE_IOU` one is dropped:
the one kept across a seam, else the weaker. A person a region read from its head map (the decoder's step 5) whose
head is another reported person's is then dropped, as the decoder drops them within a region (:func:`one_head_each`).

With each frame's people, its scene fitness is measured against the background the bundle carries
(:mod:`vc.deploy.fitness`; ``unknown`` for a bundle without one). A ``covered`` frame (black, uniform, a covered lens,
a lost signal's noise) never yields people; one whose faint contrast still shows the background's view is a veil
(below). On a frame in any other unfit state (``dark``, ``overexposed``,
``blurred``, ``moved``, ``changed``) the ``unfit`` setting decides: ``suppress`` (the default) withholds its people,
``flag`` keeps them, each marked with the frame's state (``Person.unfit``). The default suppresses because on those
frames a bundle's people are mostly invented (issue 62: a frame of 3 people read as 7 to 89 under the camera-life
conditions) and a person who is not there costs an appliance more than one it says it cannot see
(docs/decisions/0013-scene-fitness.md). How far a frame may depart from the background and stay fit is what the
bundle was compiled to see (its :class:`~vc.deploy.fitness.FitRange`: a bundle compiled over the camera's range
takes dusk, white-balance drift, night IR and a wet lens as fit, docs/decisions/0014-camera-range.md). A view that
moved or turned (a bracket settling, a knocked camera) is registered against the background up to
:data:`~vc.deploy.fitness.REGISTRATION_BOUND_PX` and :data:`~vc.deploy.fitness.REGISTRATION_BOUND_DEG` and compensated
(:mod:`vc.deploy.registration`): each frame is moved and turned back by the registration before the networks (the
region map moves with the view) and the people put forward again; the registration is kept from
frame to frame and measured again when the fitness reads a move. A frame lit beyond the bundle's exposure range
by at most :data:`~vc.deploy.exposure.REACH_STOPS` (sun on snow, a dome's glare) is brought back to the background's
exposure before the networks when it then fits (:mod:`vc.deploy.exposure`); a view under a veil beyond the range
(thick fog, glare, a camera's low contrast: ``dark`` or ``overexposed`` with a veil, or ``covered`` by a faint copy of
the view) has its contrast stretched back onto the background's tone when it then fits (:mod:`vc.deploy.veil`). The
correction is kept from frame to frame while the frames still need about as much, and the networks start on the
frame under it while the fitness is measured: a camera in such light pays for a table lookup and a second fitness a
frame, not for networks run twice.
:meth:`Runtime.run` returns the people with the fitness; ``runtime(frame)`` returns the people alone, as before, and
keeps the fitness in ``runtime.last_fitness``.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Iterable
from concurrent.futures import Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from vc.cores import usable_cores
from vc.deploy import native
from vc.deploy.areas import ImageArea
from vc.deploy.boxes import box_iou, foot_points
from vc.deploy.bundle import NO_REFERENCE, Bundle, RegionEntry, load_bundle
from vc.deploy.crop_pose import CropPoseReader, with_crop_keypoints, worth_reading
from vc.deploy.decode import (
    UPRIGHT_PRIOR,
    DecodeConfig,
    DecodedPerson,
    UprightPrior,
    decode_readings,
    one_head_each,
    with_heads_added,
)
from vc.deploy.engines import DEFAULT_ENGINE, checked_engine, graph_session
from vc.deploy.exposure import BROUGHT_BACK_AGREEMENT, KEPT_CORRECTION_STOPS, correction_stops, exposed
from vc.deploy.facing import FacingReader, face_ahead, ordered_by_facing
from vc.deploy.fitness import COVERED, DARK, MOVED, OVEREXPOSED, STATES, UNFIT_STATES, FrameFitness
from vc.deploy.native import checked_decoder
from vc.deploy.registration import Registration, view_back
from vc.deploy.veil import near, unveiled, veil_tables, veiled
from vc.errors import InputError

#: Two people of different regions overlapping more than this are one person seen by both (module docstring); lower,
#: people one behind another at a seam are lost (docs/decisions/0003-decoder-settings.md).
SEAM_DUPLICATE_IOU = 0.6
#: How far across a seam, in the person's box heights (up or down the image), a region keeps a person whose feet it
#: puts in a neighbour's owned area (module docstring). Beyond the outer edge of the regions it keeps no one: no
#: region owns that ground. On an eye-level camera a few pixels of foot are a metre of depth: without it, people the
#: region beside the seam found are dropped there (docs/decisions/0003-decoder-settings.md).
SEAM_FOOT_TOLERANCE = 0.1
#: A person kept across a seam who overlaps another region's person by more than this is that person, seen from
#: the side (:func:`without_seam_duplicates`). Lower than SEAM_DUPLICATE_IOU: letting the stronger of such a pair
#: win, or dropping it only above SEAM_DUPLICATE_IOU, doubles people at the seams
#: (docs/decisions/0003-decoder-settings.md).
ACROSS_SEAM_DUPLICATE_IOU = 0.3
#: What the runtime does with the people of an unfit frame (module docstring); a covered frame's are always withheld.
UNFIT_SETTINGS = ("suppress", "flag")
#: The runtime's setting unless told otherwise: a person who is not there costs more than one it cannot see (0013).
DEFAULT_UNFIT = "suppress"


@dataclass
class Person:
    """One detected person in frame pixels (pixel centres at integers).

    The mask is kept small: ``mask`` covers only the frame pixels ``mask_origin`` (x, y) + its shape, the bounding
    rectangle of the person's mask; :meth:`frame_mask` pastes it into a full frame.
    """

    region: str
    score: float
    box: np.ndarray  # (4,) x0, y0, x1, y1 (outer edges)
    keypoints: np.ndarray  # (17, 3) x, y, confidence
    mask: np.ndarray  # (h, w) bool
    mask_origin: tuple[int, int]  # frame pixel (x, y) of mask[0, 0]
    pair_handedness: np.ndarray | None = None  # (8,) the network's per pair (vc.deploy.decode.DecodedPerson), or the
    #                                             facing model's where the bundle has one (vc.deploy.facing)
    track: int | None = None  # set by a vc.deploy.tracking.Tracker
    facing: str = "appearance"  # what ordered the left/right pairs: "appearance" (the network or the facing model,
    #                             this frame), "motion" (the tracker, which also turned the face the way the person
    #                             walks) or "track" (the tracker, by the facing model's readings over the track)
    coasted: bool = False  # not seen in this frame: carried by its track (vc.deploy.tracking), without a mask
    weak: bool = False  # below the bundle's centre threshold: decoded only for a tracker to continue a track with
    across_seam: bool = False  # feet in a neighbour's owned area, kept within SEAM_FOOT_TOLERANCE (module docstring)
    unfit: str | None = None  # the frame's fitness state when it is unfit and its people are kept (unfit="flag")
    # the networks' handedness averaged over the pairs, kept when the facing model ordered them: the confidence a
    # tracker weighs against an unclear walk (vc.deploy.tracking; docs/decisions/0027-facing-from-the-crop.md)
    network_handedness: float | None = None
    head_found: bool = False  # read from the region network's head map (vc.deploy.decode, step 5)

    def frame_mask(self, frame_size: tuple[int, int]) -> np.ndarray:
        """The mask as an (H, W) bool array over a frame of ``frame_size`` (width, height)."""
        width, height = frame_size
        full = np.zeros((height, width), bool)
        x, y = self.mask_origin
        top, left = max(-y, 0), max(-x, 0)  # a person found on a moved-back frame may reach past its edge
        part = self.mask[top:max(height - y, 0), left:max(width - x, 0)]
        full[y + top:y + top + part.shape[0], x + left:x + left + part.shape[1]] = part
        return full

    def to_dict(self) -> dict:
        """JSON-ready: box, score, keypoints and the mask's pixel area (masks stay out of JSON Lines)."""
        return {"region": self.region, "score": round(float(self.score), 4),
                "box": [round(float(v), 2) for v in self.box],
                "keypoints": [[round(float(x), 2), round(float(y), 2), round(float(c), 4)]
                              for x, y, c in self.keypoints],
                "mask_area_px": int(self.mask.sum()), "handedness": round(self.handedness, 4),
                "facing": self.facing,
                **({"track": self.track, "coasted": self.coasted, "weak": self.weak} if self.track is not None
                   else {}),
                **({"unfit": self.unfit} if self.unfit is not None else {})}

    @property
    def handedness(self) -> float:
        """The handedness that orders the pairs, averaged over them: > 0 seen from behind, < 0 from the front; its
        size is the confidence of what read it, the facing model or the network (0 without handedness maps)."""
        return 0.0 if self.pair_handedness is None else float(np.mean(self.pair_handedness))

    @property
    def trusted_handedness(self) -> float:
        """The confidence a tracker weighs against an unclear walk: the networks' handedness, as before the facing
        model (which reads the person right for two in three on PETS09 and three in four on TUD-Stadtmitte whatever
        it says of itself), docs/decisions/0027-facing-from-the-crop.md."""
        return self.handedness if self.network_handedness is None else self.network_handedness


def just_across_seam(feet: np.ndarray, heights: np.ndarray, area: ImageArea,
                     neighbour_areas: tuple[ImageArea, ...], tolerance: float = SEAM_FOOT_TOLERANCE) -> np.ndarray:
    """Which of the people with these foot points (N, 2) and box heights (N,), frame pixels, a region with owned
    ``area`` keeps across a seam: their feet lie in one of ``neighbour_areas``, within ``tolerance`` (default
    :data:`SEAM_FOOT_TOLERANCE`) heights of ``area`` straight up or down the image (the foot point's error is the
    box bottom's; tested at quarter steps). Feet beyond every region's area are no region's."""
    in_neighbour = np.any([neighbour.contains(feet) for neighbour in neighbour_areas], axis=0)
    candidates = np.flatnonzero(in_neighbour & ~area.contains(feet))
    across = np.zeros(len(feet), bool)
    if len(candidates):
        steps = np.repeat([0.25, -0.25, 0.5, -0.5, 0.75, -0.75, 1.0, -1.0], len(candidates))  # every shift at once
        moved = np.tile(feet[candidates], (8, 1))
        moved[:, 1] += steps * tolerance * np.tile(heights[candidates], 8)
        across[candidates] = area.contains(moved).reshape(8, len(candidates)).any(axis=0)
    return across


class RegionRunner:
    """One region's graph, ready on its ``engine`` (:mod:`vc.deploy.engines`), and the mapping from its network
    input to frame pixels."""

    def __init__(self, entry: RegionEntry, frame_size: tuple[int, int], threads: int,
                 weak_people_above: float | None = None, neighbour_areas: tuple[dict, ...] = (),
                 engine: str = DEFAULT_ENGINE, decoder: str | None = None, facing: bytes | None = None,
                 crop_pose: bytes | None = None) -> None:
        self.entry = entry
        # the bundle's facing and keypoint models, a session per region: the regions run in threads of their own
        self.facing = None if facing is None else FacingReader(facing, threads)
        self.crop_pose = None if crop_pose is None else CropPoseReader(crop_pose, threads)
        self.decode = native.decode_readings if checked_decoder(decoder) == "c" else decode_readings
        self.owned_area = ImageArea(entry.owned_image_area)
        self.neighbour_areas = tuple(ImageArea(area) for area in neighbour_areas)  # the other regions' owned areas
        self.weak_people_above = weak_people_above
        self.graph = graph_session(engine, entry.model, threads)
        x0, y0, width, height = entry.crop_window
        self.origin = np.array([x0, y0], np.float64)
        self.scale = np.array([entry.input_size[0] / width, entry.input_size[1] / height])
        self.frame_size = frame_size
        self._cells_of_pixels: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}
        self.last_seconds = (0.0, 0.0)  # the last people(): network, decoding

    def heatmaps(self, frame: np.ndarray) -> np.ndarray:
        x0, y0, width, height = self.entry.crop_window
        crop = np.ascontiguousarray(frame[y0:y0 + height, x0:x0 + width])
        return self.graph(crop[None])[0]

    def to_frame(self, xy: np.ndarray) -> np.ndarray:
        """Network-input pixels -> frame pixels (pixel centres at integers in both)."""
        return self.origin + (np.asarray(xy, np.float64) + 0.5) / self.scale - 0.5

    def people(self, frame: np.ndarray) -> list[Person]:
        """The people this region owns in ``frame``, not yet :meth:`faced` (the runtime faces those the frame keeps
        once the regions' people are put together); the seconds its network and its decoding took are
        :attr:`last_seconds` (for a service's metrics)."""
        start = time.perf_counter()
        heatmaps = self.heatmaps(frame)
        decoding = time.perf_counter()
        people = self.people_in(heatmaps)
        self.last_seconds = (decoding - start, time.perf_counter() - decoding)
        return people

    def faced(self, frame: np.ndarray, people: list[Person]) -> list[Person]:
        """``people`` with their left and right ordered by the bundle's facing model where it has one, and their
        face turned where it points (:mod:`vc.deploy.facing`), then their keypoints read again from their crops by
        its keypoint model where it has one, for people tall enough for it (:mod:`vc.deploy.crop_pose`); weak
        people, for a tracker's eyes only, keep the networks' order, face and keypoints."""
        read = [person for person in people if not person.weak and person.pair_handedness is not None]
        if not read:
            return people
        boxes = np.array([person.box for person in read])
        if self.facing is not None:
            reading = self.facing.read(frame, boxes)
            for index, (person, logit) in enumerate(zip(read, reading.front_logits, strict=True)):
                person.network_handedness = person.handedness
                person.keypoints, person.pair_handedness = ordered_by_facing(person.keypoints,
                                                                             person.pair_handedness, float(logit))
                if reading.across is not None:
                    person.keypoints = face_ahead(person.keypoints, float(person.box[3] - person.box[1]),
                                                  float(reading.across[index]))
        if self.crop_pose is not None:
            tall = worth_reading(boxes)
            tall_people = [person for person, is_tall in zip(read, tall, strict=True) if is_tall]
            readings = self.crop_pose.read(frame, boxes[tall])  # none read: no crop cut
            for person, image_ordered in zip(tall_people, readings, strict=True):
                person.keypoints = with_crop_keypoints(person.keypoints, image_ordered, person.pair_handedness)
        return people

    def people_in(self, heatmaps: np.ndarray, config: DecodeConfig | None = None,
                  seam_tolerance: float = SEAM_FOOT_TOLERANCE, prior: UprightPrior = UPRIGHT_PRIOR) -> list[Person]:
        """The people this region owns in its heat maps, decoded with the bundle's settings or ``config`` (and
        ``prior``), kept across a seam within ``seam_tolerance`` (:func:`just_across_seam`); with
        ``weak_people_above``, also the weaker centre peaks down to it, flagged ``weak``. From a network with a head
        map, the people read from the heads are added to those this region keeps (the decoder's step 5)."""
        config = config or self.entry.decode
        decoded = self.decode(heatmaps, config, self.entry.expected_height_px, self.weak_people_above, prior)
        if not decoded:
            return []
        boxes = self.to_frame(np.array([person.box for person in decoded]).reshape(-1, 2)).reshape(-1, 4)
        feet = foot_points(boxes)
        inside = self.owned_area.contains(feet)
        # only the people outside the region's own area can be across a seam (usually none: no further tests)
        across, outside = np.zeros(len(feet), bool), np.flatnonzero(~inside)
        if len(outside):
            across[outside] = just_across_seam(feet[outside], boxes[outside, 3] - boxes[outside, 1],
                                               self.owned_area, self.neighbour_areas, seam_tolerance)
        # step 5 over the people kept, on their frame boxes, before their masks are cut (most heads are not added)
        kept = np.flatnonzero(inside | across)
        framed = [replace(decoded[index], box=boxes[index]) for index in kept]
        across_seam = {id(person): bool(across[index]) for person, index in zip(framed, kept, strict=True)}
        return [self._person(person, across_seam[id(person)])
                for person in with_heads_added(framed, config.max_people)]

    def _person(self, person: DecodedPerson, across_seam: bool) -> Person:
        """``person``, their box already in frame pixels, as the frame's :class:`Person`."""
        keypoints = person.keypoints.copy()
        keypoints[:, :2] = self.to_frame(keypoints[:, :2])
        mask, origin = self._frame_mask(person.mask_cells)
        return Person(self.entry.name, person.score, person.box, keypoints, mask, origin, person.pair_handedness,
                      weak=person.weak, across_seam=across_seam, head_found=person.head_found)

    def _cells_of_crop_pixels(self, cells_shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """The heat-map row of each crop pixel row and column of each crop pixel column (the cell their centres
        fall in), computed once per heat-map shape."""
        if cells_shape not in self._cells_of_pixels:
            _, _, crop_width, crop_height = self.entry.crop_window
            stride = self.entry.decode.stride
            columns = np.minimum(((np.arange(crop_width) + 0.5) * self.scale[0] / stride).astype(int),
                                 cells_shape[1] - 1)
            rows = np.minimum(((np.arange(crop_height) + 0.5) * self.scale[1] / stride).astype(int),
                              cells_shape[0] - 1)
            self._cells_of_pixels[cells_shape] = rows, columns
        return self._cells_of_pixels[cells_shape]

    def _frame_mask(self, mask_cells: np.ndarray) -> tuple[np.ndarray, tuple[int, int]]:
        """Cells -> frame pixels over the mask's bounding rectangle: each frame pixel of the crop takes the cell
        its centre falls in. Returns the mask and the frame pixel of its top-left corner."""
        x0, y0, _, _ = self.entry.crop_window
        rows, columns = self._cells_of_crop_pixels(mask_cells.shape)
        cell_rows, cell_columns = np.nonzero(mask_cells)
        if not len(cell_rows):
            return np.zeros((0, 0), bool), (x0, y0)
        # Crop pixels whose cell lies in the mask's cell rectangle (rows and columns are sorted).
        first_x = np.searchsorted(columns, cell_columns.min())
        last_x = np.searchsorted(columns, cell_columns.max(), "right")
        first_y = np.searchsorted(rows, cell_rows.min())
        last_y = np.searchsorted(rows, cell_rows.max(), "right")
        mask = mask_cells[np.ix_(rows[first_y:last_y], columns[first_x:last_x])]
        return mask, (x0 + int(first_x), y0 + int(first_y))


@dataclass
class FrameResult:
    """One frame's people and its scene fitness. ``suppressed``: the frame's people were withheld (a covered frame,
    or an unfit one under ``unfit="suppress"``): ``people`` is empty whatever the networks found."""

    people: list[Person]
    fitness: FrameFitness
    suppressed: bool = False
    network_s: float = 0.0  # the regions' networks, summed (0 when the frame's people were withheld)
    decode_s: float = 0.0  # their decoding, summed, and the facing and keypoint models on the people kept

    def reported(self, people: list[Person]) -> list[Person]:
        """What to report of ``people`` for this frame — a tracker's output for it, which adds people carried
        through the frame: none when the frame's people are withheld, each marked with the frame's state when it is
        unfit."""
        if self.suppressed:
            return []
        if self.fitness.unfit:
            for person in people:
                person.unfit = self.fitness.state
        return people


class Runtime:
    """A loaded bundle: ``runtime(frame)`` -> the people in an (H, W, 3) uint8 RGB frame.

    ``threads``: the cores to use (default: all this process may use, :func:`vc.cores.usable_cores`). With
    ``parallel_regions`` the regions run at once in a pool of that many threads, one intra-op thread each;
    otherwise one after the other, each with all ``threads``. The default (None) runs regions in parallel
    when there are several: a region's network alone does not keep two cores busy (PETS09, int8, 2 cores: 21 ms
    per frame in parallel, 28 ms in turn; benchmarks/runtime_latency.py).
    ``public_key``: a PEM Ed25519 public key (file or bytes); the bundle then loads only if its manifest is signed
    by it (:mod:`vc.deploy.signing`).
    ``weak_people_above``: also decode the centre peaks between this and the bundle's own threshold, as people
    flagged ``weak`` — for a :class:`vc.deploy.tracking.Tracker`, which keeps only those continuing a track (None:
    the bundle's people only).
    ``unfit``: ``suppress`` (default) or ``flag``, the people of a frame the scene fitness finds unfit (module
    docstring).
    ``engine``: what runs the regions' graphs, ``onnxruntime`` (default) or ``openvino`` (:mod:`vc.deploy.engines`).
    ``decoder``: what turns heat maps into people, ``c`` (the default where it is built) or ``numpy``
    (:mod:`vc.deploy.native`): the same people.
    """

    def __init__(self, bundle: Bundle | str | Path, threads: int | None = None,
                 parallel_regions: bool | None = None, public_key: Path | bytes | None = None,
                 weak_people_above: float | None = None, unfit: str = DEFAULT_UNFIT, engine: str = DEFAULT_ENGINE,
                 decoder: str | None = None):
        if isinstance(bundle, Bundle) and public_key is not None:
            raise ValueError("a public key checks a bundle as it is loaded: give the bundle's path")
        if unfit not in UNFIT_SETTINGS:
            raise InputError(None, "unfit", f"{unfit!r} is not one of {', '.join(UNFIT_SETTINGS)}")
        self.engine = checked_engine(engine)  # before the bundle is loaded: a bad setting costs nothing
        self.decoder = checked_decoder(decoder)
        self.unfit = unfit
        #: The fitness of the last frame ``runtime(frame)`` or :meth:`run` saw (None before the first).
        self.last_fitness: FrameFitness | None = None
        #: How far the view has moved (whole frame pixels) and turned from the background's, compensated on every
        #: frame until the fitness reads another move (module docstring).
        self.registration = Registration()
        #: The stops the last frame, lit beyond the range, was brought back by: the next frame's networks start on
        #: it corrected so (module docstring; None: the frames go to the networks with the light the camera gave).
        self.exposure_correction: float | None = None
        #: The tables (3, 256) the last frame, veiled beyond the range, was stretched back through: the next frame's
        #: networks start on it stretched so (module docstring; None: no veil was taken off it).
        self.veil_correction: np.ndarray | None = None
        self.bundle = bundle if isinstance(bundle, Bundle) else load_bundle(bundle, public_key)
        cores = usable_cores()
        if parallel_regions is None:
            parallel_regions = len(self.bundle.regions) > 1 and (threads or cores) > 1
        per_region = 1 if parallel_regions else (threads or cores)
        areas = [entry.owned_image_area for entry in self.bundle.regions]
        self.runners = [RegionRunner(entry, self.bundle.frame_size, per_region, weak_people_above,
                                     tuple(areas[:index] + areas[index + 1:]), engine, self.decoder,
                                     self.bundle.facing, self.bundle.crop_pose)
                        for index, entry in enumerate(self.bundle.regions)]
        self.pool = ThreadPoolExecutor(max_workers=threads or cores) if parallel_regions else None

    def reset(self) -> None:
        """Forget what the runtime carries from frame to frame (the view's registration, the last frame's tone
        correction): the next frame is measured as a camera's first (another camera, another clip)."""
        self.registration = Registration()
        self.exposure_correction, self.veil_correction = None, None
        self.last_fitness = None

    def check_frame(self, frame: np.ndarray) -> None:
        width, height = self.bundle.frame_size
        if not isinstance(frame, np.ndarray) or frame.dtype != np.uint8:
            raise InputError(None, "frame", f"expected a uint8 array, got {getattr(frame, 'dtype', type(frame))}")
        if frame.shape != (height, width, 3):
            raise InputError(None, "frame", f"expected shape {(height, width, 3)} (the bundle's camera), got "
                                            f"{frame.shape}")

    def close(self) -> None:
        """Stop the regions' thread pool; the runtime runs no frame after. ``with Runtime(...) as runtime:``
        closes it on leaving."""
        if self.pool is not None:
            self.pool.shutdown(wait=True)
        self.pool, self.runners = None, []

    def __enter__(self) -> Runtime:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def fitness(self, frame: np.ndarray) -> FrameFitness:
        """The frame's scene fitness against the bundle's background (``unknown`` without one)."""
        if self.bundle.reference is None:
            return FrameFitness.unknown(NO_REFERENCE)
        return self.bundle.reference.fitness(frame, self.bundle.fit_range)

    def run(self, frame: np.ndarray) -> FrameResult:
        """The people in an (H, W, 3) uint8 RGB frame and the frame's scene fitness (module docstring). With the
        regions in a pool, the fitness is measured in this thread while the pool runs the networks, which are
        discarded when the frame's people are withheld; otherwise first, and the networks are not run then."""
        if not self.runners:
            raise RuntimeError("this runtime was closed")
        self.check_frame(frame)
        seen = view_back(frame, self.registration)
        # the networks start on a guess, the frame as the last one was shown to them, while the fitness is measured
        guess = self._corrected(seen)
        pending = self._start(guess)
        fitness = self.fitness(seen)
        if fitness.state == MOVED and self.bundle.reference is not None:
            registration = self.bundle.reference.register(frame)
            if registration is not None:  # within the bound: the view is moved back and measured again
                self.registration = registration
                seen, guess = view_back(frame, registration), None  # the guess showed the view where it was
                fitness = self.fitness(seen)
        shown, exposure, tables = seen, None, None
        brought_back = self._brought_back(seen, fitness, guess)
        unveiled_frame = self._unveiled(seen, fitness, guess) if brought_back is None and veiled(fitness) else None
        if brought_back is not None:
            shown, fitness, exposure = brought_back
            fitness = replace(fitness, exposure_corrected_stops=exposure)
        elif unveiled_frame is not None:
            shown, judged, tables = unveiled_frame
            fitness = replace(judged, veil_taken_off=fitness.veil)
        self.exposure_correction, self.veil_correction = exposure, tables
        if not self.registration.still:
            fitness = replace(fitness, registered_px=self.registration.shift,
                              registered_roll_deg=self.registration.roll_deg or None)
        self.last_fitness = fitness
        if fitness.state == COVERED or (fitness.unfit and self.unfit == "suppress"):
            self._cancel(pending)
            return FrameResult([], fitness, suppressed=True)
        if shown is not guess:  # the guess was wrong: the networks run on the frame they are to see
            self._cancel(pending)
            pending = self._start(shown)
        per_region = ([runner.people(shown) for runner in self.runners] if pending is None
                      else [future.result() for future in pending])
        people = sorted((person for found in per_region for person in found), key=lambda person: -person.score)
        kept = one_head_each(without_seam_duplicates(people))
        facing_s = self._faced(shown, kept)
        result = FrameResult([within_frame(moved_by(person, self.registration, self.bundle.frame_size),
                                           self.bundle.frame_size) for person in kept], fitness,
                             network_s=sum(runner.last_seconds[0] for runner in self.runners),
                             decode_s=sum(runner.last_seconds[1] for runner in self.runners) + facing_s)
        result.reported(result.people)  # flagged when unfit
        return result

    def _corrected(self, seen: np.ndarray) -> np.ndarray:
        """``seen`` under the last frame's correction, if it had one: the frame the networks start on."""
        if self.veil_correction is not None:
            return unveiled(seen, self.veil_correction)
        if self.exposure_correction is not None:
            return exposed(seen, self.bundle.reference.decode, self.exposure_correction)
        return seen

    def _unveiled(self, seen: np.ndarray, fitness: FrameFitness, guess: np.ndarray | None) -> tuple[
            np.ndarray, FrameFitness, np.ndarray] | None:
        """``seen`` stretched back onto the background's tone, its fitness and the tables it went through, when
        ``fitness`` reads a view under a veil beyond the range and the frame stretched back is fit and matches the
        background (:mod:`vc.deploy.veil`); None otherwise. The last frame's tables are kept while this frame's are
        near them (``guess`` is ``seen`` through them)."""
        reference = self.bundle.reference
        tables = veil_tables(reference, seen) if reference is not None else None
        if tables is None:
            return None
        kept = guess is not None and self.veil_correction is not None and near(tables, self.veil_correction)
        frame, tables = (guess, self.veil_correction) if kept else (unveiled(seen, tables), tables)
        judged = self.fitness(frame)
        if judged.unfit or judged.matching < BROUGHT_BACK_AGREEMENT:
            return None
        return frame, judged, tables

    def _brought_back(self, seen: np.ndarray, fitness: FrameFitness, guess: np.ndarray | None) -> tuple[
            np.ndarray, FrameFitness, float] | None:
        """``seen`` brought back to the background's exposure, its fitness and the stops it was changed by, when
        ``fitness`` reads it ``dark`` or ``overexposed`` within reach of the bundle's range and the frame brought
        back is fit and matches the background (:mod:`vc.deploy.exposure`); None otherwise: the frame stays as it
        was judged. The last frame's correction (``guess`` is ``seen`` under it, when there was one) is kept while
        it is within :data:`~vc.deploy.exposure.KEPT_CORRECTION_STOPS` of this frame's: the networks were started on
        it."""
        reference, fit_range = self.bundle.reference, self.bundle.fit_range
        if fitness.state not in (DARK, OVEREXPOSED) or reference is None:
            return None
        stops = correction_stops(fitness.exposure_stops, fit_range.dark_stops, fit_range.overexposed_stops)
        if stops is None:
            return None
        kept = guess is not None and self.exposure_correction is not None \
            and abs(stops - self.exposure_correction) <= KEPT_CORRECTION_STOPS
        frame, stops = (guess, self.exposure_correction) if kept else (exposed(seen, reference.decode, stops), stops)
        judged = self.fitness(frame)
        if judged.unfit or judged.matching < BROUGHT_BACK_AGREEMENT:
            return None
        return frame, judged, stops

    def _faced(self, frame: np.ndarray, people: list[Person]) -> float:
        """Each region's people of ``people`` faced by its runner (:meth:`RegionRunner.faced`, in place; in the pool
        where there is one), once the seam and one-head rules have dropped those a neighbour reports: a person
        dropped costs no facing or keypoint model. Returns the seconds it took."""
        start = time.perf_counter()
        groups = [(runner, [person for person in people if person.region == runner.entry.name])
                  for runner in self.runners]
        groups = [(runner, group) for runner, group in groups if group]
        if self.pool is None or len(groups) < 2:
            for runner, group in groups:
                runner.faced(frame, group)
        else:
            for future in [self.pool.submit(runner.faced, frame, group) for runner, group in groups]:
                future.result()
        return time.perf_counter() - start

    def _start(self, frame: np.ndarray) -> list[Future] | None:
        """The regions' networks started on ``frame`` in the pool (None without one: they run when needed)."""
        return [self.pool.submit(runner.people, frame) for runner in self.runners] if self.pool is not None else None

    @staticmethod
    def _cancel(pending: list[Future] | None) -> None:
        if pending is not None:
            for future in pending:
                future.cancel()
            wait(pending)

    def fitness_summary(self, frames: Iterable[FrameFitness]) -> dict:
        """A run's scene fitness for its summary, from each frame's fitness: frames per state (in
        :data:`~vc.deploy.fitness.STATES` order), how many were unfit, the ``unfit`` setting, how many were brought
        back from light beyond the range (``exposure_corrected_stops``), had a veil beyond it taken off
        (``veil_taken_off``) or their view moved or turned back (``registered_px``) and, without a reference, why
        every frame is unknown."""
        frames = list(frames)
        states = Counter(fitness.state for fitness in frames)
        return {"states": {state: states[state] for state in STATES if states.get(state)},
                "unfit_frames": sum(states.get(state, 0) for state in UNFIT_STATES), "unfit": self.unfit,
                "exposure_corrected_frames": sum(fitness.exposure_corrected_stops is not None for fitness in frames),
                "veil_taken_off_frames": sum(fitness.veil_taken_off is not None for fitness in frames),
                "registered_frames": sum(fitness.registered_px is not None for fitness in frames),
                **({} if self.bundle.reference is not None else {"unknown_because": NO_REFERENCE})}

    def __call__(self, frame: np.ndarray) -> list[Person]:
        """The people in an (H, W, 3) uint8 RGB frame (:meth:`run`'s, without the fitness: ``last_fitness``)."""
        return self.run(frame).people


def moved_by(person: Person, registration: Registration, frame_size: tuple[int, int]) -> Person:
    """``person``, found on a frame moved and turned back by ``registration``, in the frame's own pixels (the same
    object, changed). The keypoints follow the view; the box and the mask follow its centre and keep their size and
    pixels: the registrations turn a fraction of a degree to a few, which changes a person's box by a pixel or two."""
    if registration.still:
        return person
    x0, y0, x1, y1 = person.box
    centre = np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0])
    dx, dy = registration.forward(centre, frame_size)[0] - centre
    person.box = person.box + np.array([dx, dy, dx, dy], person.box.dtype)
    keypoints = person.keypoints.copy()
    keypoints[:, :2] = registration.forward(keypoints[:, :2], frame_size)
    person.keypoints = keypoints
    person.mask_origin = (person.mask_origin[0] + int(round(dx)), person.mask_origin[1] + int(round(dy)))
    return person


def within_frame(person: Person, frame_size: tuple[int, int]) -> Person:
    """``person`` with the box clipped to the frame of ``frame_size`` (width, height; the same object, changed). A
    person the frame's edge cuts is boxed as the camera shows them, as annotators draw them: the decoded box, laid
    around the centre at the person's expected width, reaches past the edge
    (docs/decisions/0020-people-cut-by-the-frame.md)."""
    width, height = frame_size
    x0, y0, x1, y1 = person.box
    person.box = np.array([min(max(x0, -0.5), width - 0.5), min(max(y0, -0.5), height - 0.5),
                           min(max(x1, -0.5), width - 0.5), min(max(y1, -0.5), height - 0.5)], person.box.dtype)
    return person


def without_seam_duplicates(people: list[Person], iou: float = SEAM_DUPLICATE_IOU) -> list[Person]:
    """``people`` (strongest first) without those overlapping a person of another region by more than ``iou``: one
    person kept by two regions at their seam. The one kept across the seam gives way to the owner's, whatever
    their scores (the owner's network was trained on people standing there), and already where they overlap by
    more than :data:`ACROSS_SEAM_DUPLICATE_IOU`; otherwise the weaker gives way. A weak person (decoded for a
    tracker only) never removes another. People of one region are the decoder's to separate."""
    kept: list[Person] = []
    # stable: strongest first within each of strong owners', strong across a seam, weak owners', weak across
    for person in sorted(people, key=lambda person: (person.weak, person.across_seam)):
        others = [other.box for other in kept if other.region != person.region]
        limit = ACROSS_SEAM_DUPLICATE_IOU if person.across_seam else iou
        if others and box_iou(person.box[None], np.array(others))[0].max() > limit:
            continue
        kept.append(person)
    kept_ids = {id(person) for person in kept}
    return [person for person in people if id(person) in kept_ids]
