"""People over time: tracks, people carried through the frames that miss them, and which way each person faces
from the way they walk (numpy only).

Why: which member of a left/right pair is the person's left depends on which way they face. A network reads
it from appearance (:mod:`vc.deploy.heatmaps`' handedness maps), and where people are small it often cannot: on
PETS09 (people ~50 px tall) the bundles read 45 % of real people facing the wrong way (docs/pose.md). A walking
person faces where they walk, and the camera's geometry turns the direction of walking into facing without
knowing the camera:

* The vertical plane through the camera centre and a person's feet projects onto the person's own image axis
  (the line from feet to head). The part of their ground velocity along the viewing direction therefore moves
  the feet along that axis; the rest moves them across it.
* A camera above the ground sees farther ground higher in the image. Feet moving up the image walk away from the
  camera: the person is seen from behind, their left on the image's left (handedness > 0). Feet moving down
  walk toward it: seen from the front (handedness < 0).

People are upright in the views this project compiles (the decoder's prior assumes it), so the image axis is
taken as the image vertical. Checked on ground-truth tracks: the sign of the vertical foot motion agrees with
YOLO11n-pose's reading of the shoulders for most people whose facing it can read
(docs/decisions/0007-facing-and-tracking.md).

Why carry people through frames: a network on single frames loses people for a frame or two when someone walks
in front of them or their appearance flickers, most in crowds (TUD-Stadtmitte at 25 frames/s). A track seen a few
times and lost for less than ``coast_s`` is still reported, where its motion puts it, at a score that falls with
the time unseen: precision pays little, as the score ranks it below what is seen.

1. Association: each person goes to the live track whose foot point (box bottom centre, frame pixels), moved on
   by the track's velocity (least squares over its window) to this frame, is nearest, in units of the person's
   box height, if within ``gate_heights + max_speed_heights_per_s * dt``; pairs are taken nearest first, each
   person and track once. Given the frame, the distance also counts how unlike the track's clothes the person's
   are (:func:`appearance`: colour histograms of the mask's pixels above and below the waist, a running mean per
   track; ``appearance_weight`` heights for no colour in common): in a group, detections jitter by more than
   people stand apart, and position alone hands one person's track to a neighbour. A person without a track
   starts one. A track not seen for ``max_gap_s`` ends. (Without the velocity, tracks hopped between people
   walking close together: IDF1 0.46 against 0.63 on PETS09.)
   1b. Weak people (``Person.weak``: centre peaks below the bundle's threshold, decoded down to
   ``weak_people_above`` for the tracker) are then matched the same way to the tracks still unmatched that were
   seen at least ``coast_min_observations`` times; a weak person who continues no such track is dropped. A person
   half hidden by another or blurred for a frame keeps their track with their own box rather than a carried one
   (the idea of ByteTrack, Zhang et al., 2022).
2. Motion: the least-squares speed of the track's foot height in the image over its last ``window_s`` seconds
   (in person heights per second) and its standard error (the fit's residuals, floored at
   ``foot_jitter_heights``).
3. Facing: the motion's sign where the speed is at least ``min_significance`` standard errors from zero. Where
   it is less clear, still the motion's sign unless the network is confident (``|trusted_handedness| >=
   trust_network``): a network hedging near zero (people too small for it to see which way they face; PETS09) is
   no better than a weak motion, while one that learned facing (TUD-Stadtmitte's larger people) is right more often
   than an unclear motion. The confidence weighed is the networks' even where a bundle's facing model ordered the
   pairs: the model is as sure of the people it reads wrong (docs/decisions/0027-facing-from-the-crop.md). A track
   of fewer than ``min_observations`` in the window, or no motion at all, leaves the order appearance gave; so does
   a box whose height changes faster than ``max_walk_growth_per_s`` (its log a second, fitted like the speed): that
   is a person coming out from behind another, or going behind them, whose box bottom moves with what hides their
   legs. At eye level it looks just like a walk toward or away from the camera (the head stays on the horizon and
   only the feet move), and there the walk read three in four such people the wrong way round
   (docs/decisions/0028-a-walk-that-is-not-a-walk.md).
   People the bundle's facing model read are instead ordered, wherever their walk is not clear (or not a walk, or
   too short to tell), by the sign of that model's handedness averaged over the track's last ``facing_vote_s``
   seconds (:func:`model_reading`; ``facing == "track"``): its readings of one person err frame by frame, and a
   person standing, turning or coming out from behind another does not walk the way they face
   (docs/decisions/0044-facing-voted-over-the-track.md). That holds for small people, read once by the head's
   colours, as for tall ones read twice (docs/decisions/0047-small-people-voted-over-the-track.md). A clear walk
   decides for them too, unless that vote reads them the other way at least ``vote_overrules_walk`` surely: someone
   who has stopped, turned or is stepping back still drifts clearly on their feet, and the model's readings over
   seconds are then the better cue (docs/decisions/0049-a-sure-vote-overrules-the-walk.md).
4. A person whose facing came from motion gets each left/right pair put in the image order that facing implies,
   and their face turned the way they walk (:func:`vc.deploy.facing.face_ahead`): the nose and the eyes are put
   ahead of the ears' midpoint, toward the side the feet move to, by the share of the walk that crosses the view
   (the foot point's horizontal speed over ``profile_speed_heights_per_s``, at most 1: a person crossing the view
   is seen in profile, one walking along it from the front or back). Elsewhere the face stays where the bundle's
   facing model turned it, each frame on its own (:mod:`vc.deploy.facing`).
5. Carried: a track of at least ``coast_min_observations`` unseen for at most ``coast_s`` is reported
   (``coasted``) with its last box and keypoints moved by the least-squares velocity of its box over the window,
   its score times ``exp(-unseen / coast_score_decay_s)`` and no mask, unless that box overlaps a person seen in
   this frame by more than ``coast_duplicate_iou`` (the same person, under a new track). Given the frame, one
   whose feet that velocity took out of it walked out and is not reported; the others are clipped to it
   (:func:`kept_to_frame`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from vc.deploy.boxes import box_iou, foot_points
from vc.deploy.facing import face_ahead
from vc.deploy.frames import FrameSource
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Person, within_frame

#: Levels per RGB channel of the colour histograms that tell people apart (4: 64 colours, coarse enough for a
#: person's clothes to keep theirs under changing light) and how much of a track's histogram each sighting renews.
APPEARANCE_LEVELS = 4
APPEARANCE_RENEWAL = 0.3


@dataclass(frozen=True)
class TrackingConfig:
    """How people are followed and when their motion decides which way they face (see the module docstring).
    Lengths are in the person's box heights, times in seconds."""

    gate_heights: float = 0.15  # detection jitter allowed between two frames, whatever their distance in time
    max_speed_heights_per_s: float = 1.5  # a brisk walk (2.5 m/s) for a 1.7 m person
    max_gap_s: float = 1.0  # a track unseen this long ends
    window_s: float = 1.0  # the motion of the last second decides the facing
    min_observations: int = 4
    foot_jitter_heights: float = 0.02  # the least noise assumed on a foot point
    min_significance: float = 2.0  # speed / its standard error
    # a walk across the view this fast is seen in full profile (1.3 m/s, a comfortable walk, for a 1.7 m person)
    profile_speed_heights_per_s: float = 0.75
    trust_network: float = 0.3  # where the motion is not clear, a network this confident keeps its facing
    # a box growing or shrinking faster than this (its log height a second; a walker 3.5 m away coming at 1.4 m/s)
    # is a person coming out from behind another or going behind them, not a walk, and the walk does not decide
    # their facing (docs/decisions/0028-a-walk-that-is-not-a-walk.md); inf: it always may
    max_walk_growth_per_s: float = 0.4
    # the seconds of a person's facing-model readings that vote where the walk is not clear
    # (docs/decisions/0044-facing-voted-over-the-track.md)
    facing_vote_s: float = 3.0
    # a vote at least this sure the other way (of 1) overrules a clear walk
    # (docs/decisions/0049-a-sure-vote-overrules-the-walk.md); inf: it never does
    vote_overrules_walk: float = 0.5
    coast_s: float = 0.5  # a track unseen up to this long is still reported (0: never)
    coast_min_observations: int = 3  # a track seen this often is a person, not a passing false alarm
    coast_score_decay_s: float = 1.0
    coast_duplicate_iou: float = 0.7
    # With frames given to update(): what a complete mismatch of clothing colours adds to a pair's distance, in
    # heights (0: motion alone): people walking close together swap tracks less
    # (docs/decisions/0007-facing-and-tracking.md).
    appearance_weight: float = 0.3
    # The runtime also decodes centre peaks down to this, as weak people (Runtime(weak_people_above=...)): a weak
    # person only continues a track seen coast_min_observations times, and is dropped otherwise.
    weak_people_above: float = 0.1


@dataclass
class _Track:
    """One person's observations within the motion window (older ones are dropped: an appliance runs for
    months), their count ever, and the last person seen."""

    identity: int
    times: list[float] = field(default_factory=list)
    boxes: list[np.ndarray] = field(default_factory=list)  # (4,) frame px
    readings: list[tuple[float, float]] = field(default_factory=list)  # (time, model_reading) within a vote
    observations: int = 0
    last: Person | None = None
    appearance: np.ndarray | None = None  # (2, 64) running mean of the person's colour histograms

    def add(self, time_s: float, box: np.ndarray, window_s: float) -> None:
        keep = [k for k, t in enumerate(self.times) if t >= time_s - window_s]
        self.times = [self.times[k] for k in keep] + [time_s]
        self.boxes = [self.boxes[k] for k in keep] + [np.asarray(box, np.float64)]
        self.observations += 1

    def read(self, time_s: float, reading: float, vote_s: float) -> None:
        """Keeps a :func:`model_reading` of this sighting, and those of the last ``vote_s`` seconds."""
        self.readings = [(t, r) for t, r in self.readings if t >= time_s - vote_s] + [(time_s, reading)]

    def facing_vote(self, time_s: float, vote_s: float) -> float:
        """The facing model's readings of the last ``vote_s`` seconds to ``time_s``, averaged (> 0 seen from behind;
        0 without any)."""
        recent = [r for t, r in self.readings if t >= time_s - vote_s]
        return sum(recent) / len(recent) if recent else 0.0

    def shift(self, time_s: float) -> np.ndarray:
        """How far (4,) the last box moves by ``time_s`` at the window's velocity, frame px."""
        return box_velocity(np.array(self.times), np.array(self.boxes)) * (time_s - self.times[-1])

    def predicted_foot(self, time_s: float) -> np.ndarray:
        """Where the feet are at ``time_s`` if they keep the window's velocity."""
        return foot_points(self.boxes[-1] + self.shift(time_s))[0]


def tracking_rate(source: FrameSource, fps: float | None) -> float | None:
    """Frames per second to track ``source``'s frames at: ``fps`` where given, else a video's own rate; None (no
    tracking) for a folder of frames without ``fps`` or a single image, whose times are unknown."""
    if fps is not None:
        return fps
    return source.fps if source.kind == "video" else None


def foot_speed(times: np.ndarray, foot: np.ndarray, height: float, jitter_heights: float) -> tuple[float, float]:
    """Least-squares speed of one coordinate of the foot point (person heights per second; y: > 0 down the image,
    toward the camera; x: > 0 to the image's right) and its standard error, the residuals' variance floored at
    ``jitter_heights`` squared (step 2)."""
    # sum / count rather than .mean(): the same numbers, without numpy's per-call overhead on a handful of values
    # (the tracker fits two of these per person per frame)
    t = times - times.sum() / len(times)
    position = foot / height
    spread = float(t @ t)
    if len(t) < 3 or spread <= 0.0:
        return 0.0, float("inf")
    centred = position - position.sum() / len(position)
    slope = float(t @ centred / spread)
    residuals = centred - slope * t
    variance = max(float(residuals @ residuals) / (len(t) - 2), jitter_heights**2)
    return slope, float(np.sqrt(variance / spread))


def facing_pairs(person: Person, seen_from_behind: bool) -> np.ndarray:
    """The person's keypoints (17, 3) with each left/right pair ordered as a facing implies: the network's
    image-left member is the left one for a person seen from behind, the right one for a person seen from the
    front. The decoder ordered pair k by the sign of ``pair_handedness[k]``; a pair whose sign disagrees is
    exchanged. A person without handedness (not decoded from a network's maps) has the members' x order stand in for
    the network's image order."""
    if person.pair_handedness is not None:
        return swap_pairs(person.keypoints, (person.pair_handedness >= 0) != seen_from_behind)
    image_left_first = [person.keypoints[left, 0] <= person.keypoints[right, 0] for left, right in PAIRS]
    return swap_pairs(person.keypoints, np.array(image_left_first) != seen_from_behind)


def model_reading(person: Person) -> float | None:
    """The bundle's facing model's handedness for a person it read (> 0 seen from behind, its size the model's
    confidence), which a track averages (step 3); None for a person it did not read (a bundle without one, a
    weak person), whose order the networks gave."""
    if person.network_handedness is None:
        return None
    return person.handedness


def _by_vote(person: Person, track: _Track, vote_s: float) -> Person:
    """Step 3 for a person the facing model read and whose walk is not clear: pairs ordered by the sign of
    the track's vote over ``vote_s`` seconds (:meth:`_Track.facing_vote`), their face left as the model turned it."""
    vote = track.facing_vote(track.times[-1], vote_s)
    if vote == 0.0:
        return person
    return replace(person, keypoints=facing_pairs(person, seen_from_behind=vote > 0), facing="track")


def appearance(person: Person, frame: np.ndarray) -> np.ndarray | None:
    """Colour histograms (2, 64), each summing to 1, of the frame's pixels under the person's mask, upper half and
    lower half (clothes above and below the waist); None for a person without mask pixels."""
    rows, columns = np.nonzero(person.mask)
    if not len(rows):
        return None
    x, y = person.mask_origin
    levels = (frame[y + rows, x + columns] // (256 // APPEARANCE_LEVELS)).astype(np.intp)  # (N, 3)
    colours = (levels[:, 0] * APPEARANCE_LEVELS + levels[:, 1]) * APPEARANCE_LEVELS + levels[:, 2]
    upper = rows < (rows[0] + rows[-1] + 1) // 2  # rows come sorted
    histograms = np.stack([np.bincount(colours[upper], minlength=APPEARANCE_LEVELS**3),
                           np.bincount(colours[~upper], minlength=APPEARANCE_LEVELS**3)]).astype(np.float64)
    return histograms / np.maximum(histograms.sum(axis=1, keepdims=True), 1.0)


def appearance_distance(a: np.ndarray, b: np.ndarray) -> float:
    """1 - the Bhattacharyya coefficient of two people's histograms, averaged over the halves both have pixels in:
    0 for the same colours, 1 for none in common."""
    both = (a.sum(axis=1) > 0) & (b.sum(axis=1) > 0)
    if not both.any():
        return 0.0
    return float(1.0 - np.sqrt(a[both] * b[both]).sum(axis=1).mean())


class Tracker:
    """``tracker.update(people, time_s, frame)`` -> the same people with ``track`` set and, where their motion
    tells which way they face, their pairs ordered and faces turned by it (``facing == "motion"``). Feed frames in
    time order; without ``frame``, people are told apart by position alone."""

    def __init__(self, config: TrackingConfig = TrackingConfig()) -> None:
        self.config = config
        self.tracks: list[_Track] = []
        self.next_identity = 1
        self.last_time: float | None = None

    def update(self, people: list[Person], time_s: float, frame: np.ndarray | None = None) -> list[Person]:
        """``frame`` (H, W, 3), the one the people were found in: with ``config.appearance_weight``, their
        clothing colours weigh in the association, and people carried out of it are not reported."""
        if self.last_time is not None and time_s <= self.last_time:
            raise ValueError(f"frames must come in time order: {time_s} s after {self.last_time} s")
        self.last_time = time_s
        config = self.config
        self.tracks = [t for t in self.tracks if time_s - t.times[-1] <= config.max_gap_s]
        looks = ({id(p): appearance(p, frame) for p in people}
                 if frame is not None and config.appearance_weight > 0 else {})
        predicted = {id(track): track.predicted_foot(time_s) for track in self.tracks}
        strong = [p for p in people if not p.weak]
        weak = [p for p in people if p.weak]
        matched = list(zip(strong, self._associate(strong, self.tracks, time_s, True, looks, predicted), strict=True))
        taken = {id(track) for _, track in matched}
        confirmed = [t for t in self.tracks if id(t) not in taken and t.observations >= config.coast_min_observations]
        matched += [(person, track) for person, track in
                    zip(weak, self._associate(weak, confirmed, time_s, False, looks, predicted), strict=True) if track]
        result = []
        for person, track in matched:
            track.add(time_s, person.box, config.window_s)
            reading = model_reading(person)
            if reading is not None:
                track.read(time_s, reading, config.facing_vote_s)
            look = looks.get(id(person))
            if look is not None:
                track.appearance = look if track.appearance is None else (
                    (1 - APPEARANCE_RENEWAL) * track.appearance + APPEARANCE_RENEWAL * look)
            track.last = self._faced(replace(person, track=track.identity), track, voted=reading is not None)
            result.append(track.last)
        seen = {id(track) for _, track in matched}
        boxes = np.array([p.box for p in result], np.float64).reshape(-1, 4)
        carried = self._carried([t for t in self.tracks if id(t) not in seen], boxes, time_s)
        return result + (carried if frame is None else kept_to_frame(carried, (frame.shape[1], frame.shape[0])))

    def _associate(self, people: list[Person], tracks: list[_Track], time_s: float, start_new: bool,
                   looks: dict[int, np.ndarray | None], predicted: dict[int, np.ndarray]) -> list[_Track | None]:
        """Step 1: each person's track among ``tracks``; without one, a new track or None. ``looks``: the people's
        colour histograms by ``id``, where they weigh in; ``predicted``: each track's foot point at ``time_s``,
        by the track's ``id``."""
        config = self.config
        boxes = np.array([p.box for p in people], np.float64).reshape(-1, 4)
        feet, heights = foot_points(boxes), np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)
        expected = np.array([predicted[id(track)] for track in tracks], np.float64).reshape(-1, 2)
        gates = config.gate_heights + config.max_speed_heights_per_s * (
            time_s - np.array([track.times[-1] for track in tracks], np.float64))
        distances = np.hypot(feet[:, None, 0] - expected[None, :, 0],
                             feet[:, None, 1] - expected[None, :, 1]) / heights[:, None]  # (people, tracks)
        rows, columns = np.nonzero(distances <= gates[None, :])
        costs = distances[rows, columns]
        for k, (i, j) in enumerate(zip(rows.tolist(), columns.tolist(), strict=True)):
            look, track_look = looks.get(id(people[i])), tracks[j].appearance
            if look is not None and track_look is not None:
                costs[k] += config.appearance_weight * appearance_distance(look, track_look)
        assigned: dict[int, _Track] = {}
        taken: set[int] = set()
        for k in np.lexsort((columns, rows, costs)).tolist():  # cheapest first; ties in (person, track) order
            i, j = int(rows[k]), int(columns[k])
            if i not in assigned and j not in taken:
                assigned[i] = tracks[j]
                taken.add(j)
        result: list[_Track | None] = []
        for i in range(len(people)):
            if i not in assigned and start_new:
                assigned[i] = _Track(self.next_identity)
                self.next_identity += 1
                self.tracks.append(assigned[i])
            result.append(assigned.get(i))
        return result

    def _faced(self, person: Person, track: _Track, voted: bool) -> Person:
        """Steps 2-4 for one person whose track now ends with this frame; ``voted``: the facing model read them
        (:func:`model_reading`)."""
        config = self.config

        def not_by_the_walk() -> Person:
            return _by_vote(person, track, config.facing_vote_s) if voted else person

        if len(track.times) < config.min_observations:  # the track holds its window's observations only
            return not_by_the_walk()
        boxes, times = np.array(track.boxes), np.array(track.times)
        feet, height = foot_points(boxes), float((boxes[:, 3] - boxes[:, 1]).sum() / len(boxes))
        speed, error = foot_speed(times, feet[:, 1], height, config.foot_jitter_heights)
        clear = abs(speed) >= config.min_significance * error
        if speed == 0.0 or not (clear or (not voted and abs(person.trusted_handedness) < config.trust_network)):
            return not_by_the_walk()
        # the vote is > 0 for seen from behind, the walk's speed < 0 (away, up the image) for the same
        if voted and float(np.sign(speed)) * track.facing_vote(track.times[-1], config.facing_vote_s) >= \
                config.vote_overrules_walk:
            return not_by_the_walk()
        # a box of no height (clipped to the frame's edge) counts as 1 px, as in the association
        heights = np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)
        growth, _ = foot_speed(times, np.log(heights), 1.0, config.foot_jitter_heights)
        if abs(growth) > config.max_walk_growth_per_s:
            return not_by_the_walk()
        across, _ = foot_speed(times, feet[:, 0], height, config.foot_jitter_heights)
        keypoints = face_ahead(facing_pairs(person, seen_from_behind=speed < 0), float(person.box[3] - person.box[1]),
                               float(np.clip(across / config.profile_speed_heights_per_s, -1.0, 1.0)))
        return replace(person, keypoints=keypoints, facing="motion")

    def _carried(self, unseen: list[_Track], seen_boxes: np.ndarray, time_s: float) -> list[Person]:
        """Step 5: the people of tracks unseen in this frame that are still reported."""
        config = self.config
        carried = []
        for track in unseen:
            elapsed = time_s - track.times[-1]
            if elapsed > config.coast_s or track.observations < config.coast_min_observations:
                continue
            shift = track.shift(time_s)
            box = track.boxes[-1] + shift
            if len(seen_boxes) and box_iou(box[None], seen_boxes).max() > config.coast_duplicate_iou:
                continue
            last = track.last
            keypoints = last.keypoints.copy()
            keypoints[:, :2] += foot_points(shift)[0]  # moved as the feet move
            carried.append(replace(last, score=last.score * float(np.exp(-elapsed / config.coast_score_decay_s)),
                                   box=box, keypoints=keypoints, mask=np.zeros((0, 0), bool),
                                   mask_origin=(0, 0), coasted=True))
        return carried


#: A carried person's feet may lie this far below the frame's bottom edge (box heights) and still be in view: a near
#: person's feet are cut by it, and their box, clipped to the frame, ends there.
FEET_BELOW_FRAME_HEIGHTS = 0.1


def kept_to_frame(carried: list[Person], frame_size: tuple[int, int]) -> list[Person]:
    """``carried`` people (step 5) in the frame of ``frame_size`` (width, height): one whose feet have left it
    (beyond its sides, or below its bottom by more than :data:`FEET_BELOW_FRAME_HEIGHTS`) walked out and is dropped;
    the others' boxes are clipped to it, as the runtime clips the people it finds
    (docs/decisions/0020-people-cut-by-the-frame.md)."""
    width, height = frame_size
    kept = []
    for person in carried:
        x0, y0, x1, y1 = person.box
        feet_x = (x0 + x1) / 2
        if -0.5 <= feet_x <= width - 0.5 and y1 <= height - 0.5 + FEET_BELOW_FRAME_HEIGHTS * (y1 - y0):
            kept.append(within_frame(person, frame_size))
    return kept


def box_velocity(times: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Least-squares velocity (4,) of boxes (N, 4) over times (N,), frame px per second; zero from one box."""
    t = times - times.sum() / len(times)  # as in foot_speed
    spread = float(t @ t)
    if spread <= 0.0:
        return np.zeros(4)
    return t @ (boxes - boxes.sum(axis=0) / len(boxes)) / spread
