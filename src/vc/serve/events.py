"""A camera's tracked people as events: a track's ``new``, its ``update``\\ s and its ``end``.

1. A track is announced (``new``) once it has been seen ``confirm_observations`` times: the tracker's own count
   for a person rather than a passing false alarm (:class:`vc.deploy.tracking.TrackingConfig`'s
   ``coast_min_observations``), so one-frame ghosts make no events.
2. An announced track reported in a frame gets an ``update`` when ``update_interval_s`` has passed since its last
   event, or at once when the zones its feet stand in changed.
3. A track the tracker no longer keeps (unseen for its ``max_gap_s``: ``reason: unseen``), or every live track
   when the service stops (``reason: shutdown``), gets an ``end`` with its last position and the time it was
   last seen, and leaves the zones it was in.

Each event carries a unique ``id`` (a UUID), the camera, the track, the frame it came from (number, and the wall
time it was read), the person's box, keypoints and score in frame pixels, where their feet stand on the ground in
metres (through the bundle's camera; None above the horizon), and the zones they are in, entered and left.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass, field

import numpy as np

from vc.deploy.boxes import foot_points
from vc.deploy.runtime import Person
from vc.deploy.zones import SceneZones

EVENT_TYPES = ("new", "update", "end")


@dataclass
class _TrackRecord:
    first_time: float
    last_seen_time: float
    observations: int = 0
    announced: bool = False
    last_event_time: float = -np.inf
    zones: tuple[str, ...] = ()
    last: dict = field(default_factory=dict)  # the last position fields published or seen


def _round(values: np.ndarray, digits: int) -> list:
    return np.round(np.asarray(values, np.float64), digits).tolist()


class TrackEvents:
    """Events of one camera's tracks (see the module docstring)."""

    def __init__(self, camera: str, zones: SceneZones, update_interval_s: float, confirm_observations: int) -> None:
        self.camera, self.zones = camera, zones
        self.update_interval_s, self.confirm_observations = update_interval_s, confirm_observations
        self.tracks: dict[int, _TrackRecord] = {}

    def update(self, people: list[Person], live_tracks: set[int], time_s: float, wall_time: float,
               frame: int) -> list[dict]:
        """The events of one frame: ``people`` as the tracker reported them, ``live_tracks`` the identities it still
        keeps, ``time_s`` the frame's time on the tracker's clock."""
        events = []
        tracked = [person for person in people if person.track is not None]
        feet = foot_points(np.array([p.box for p in tracked], np.float64).reshape(-1, 4))
        ground = self.zones.ground_points(feet)
        inside = self.zones.zones_at(feet, ground)
        for person, foot, on_ground, zones in zip(tracked, feet, ground, inside, strict=True):
            record = self.tracks.setdefault(person.track, _TrackRecord(time_s, time_s))
            if not person.coasted:
                record.observations += 1
                record.last_seen_time = time_s
            position = self._position(person, foot, on_ground, frame, wall_time)
            entered = [name for name in zones if name not in record.zones]
            left = [name for name in record.zones if name not in zones]
            if not record.announced:
                record.zones, record.last = tuple(zones), position
                if record.observations >= self.confirm_observations:
                    record.announced = True
                    events.append(self._event("new", person.track, record, time_s, position, list(zones), []))
                continue
            if entered or left or time_s - record.last_event_time >= self.update_interval_s:
                events.append(self._event("update", person.track, record, time_s, position, entered, left,
                                          zones=tuple(zones)))
            else:
                record.last = position
                record.zones = tuple(zones)
        for identity in [t for t in self.tracks if t not in live_tracks]:
            events += self._ended(identity, time_s, "unseen")
        return events

    def end_all(self, time_s: float, reason: str) -> list[dict]:
        """``end`` for every live track (the service stopping: subscribers keep no ghosts)."""
        return [event for identity in list(self.tracks) for event in self._ended(identity, time_s, reason)]

    def _ended(self, identity: int, time_s: float, reason: str) -> list[dict]:
        record = self.tracks.pop(identity)
        if not record.announced:
            return []
        return [self._event("end", identity, record, record.last_seen_time, record.last, [], list(record.zones),
                            zones=(), reason=reason)]

    def _position(self, person: Person, foot: np.ndarray, on_ground: np.ndarray, frame: int,
                  wall_time: float) -> dict:
        return {"frame": frame, "time": round(wall_time, 3), "score": round(float(person.score), 4),
                "box": _round(person.box, 2), "keypoints": _round(person.keypoints, 2),
                "foot_px": _round(foot, 2),
                "ground_m": _round(on_ground, 3) if np.isfinite(on_ground).all() else None,
                "carried": bool(person.coasted)}

    def _event(self, kind: str, identity: int, record: _TrackRecord, time_s: float, position: dict,
               entered: list[str], left: list[str], zones: tuple[str, ...] | None = None,
               reason: str | None = None) -> dict:
        if zones is not None:
            record.zones = zones
        record.last, record.last_event_time = position, time_s
        # duration: from the track's first frame to this one (an end: to the last frame it was seen in)
        event = {"id": uuid.uuid4().hex, "type": kind, "camera": self.camera, "track": identity, **position,
                 "zones": list(record.zones), "entered": entered, "left": left,
                 "duration_s": round(time_s - record.first_time, 3)}
        if reason is not None:
            event["reason"] = reason
        return event
