"""Which cue tells a walker, whose walk says which way they face, from a person who has stopped or turned, whom the
facing model's vote over the track reads better? Pose agreement with YOLO11n-pose @1280 tracked, both halves
(frozen, issue 57; follows decision 0048).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-walk-clarity \
        python experiments/2026-12-02-walker-or-not/cues.py BUNDLE SEED CAMERA >> results/arms.jsonl

Each arm is the shipped tracker (main at 09ddb7a) whose step 3 takes one more cue before a clear walk decides:
* ``a walk of at least S heights/s``: the walk must also be that fast toward or away from the camera (a clear but
  slow drift of the feet is a person standing, shifting their weight);
* ``the vote overrules a walk at V``: where the facing model's readings over the last 3 s average at least V (of 1)
  the other way, the vote decides.
Each frame runs once through the bundle as shipped; every arm's tracker is fed a copy of its people (walk-clarity's
``half`` with these arms). PETS09 tracked at 10 frames/s (0046), TUD-Stadtmitte at 25.
"""

from __future__ import annotations

from dataclasses import replace

import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring
import numpy as np

from vc.deploy.boxes import foot_points
from vc.deploy.facing import face_ahead
from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker, TrackingConfig, _by_vote, _Track, facing_pairs, foot_speed


class CueTracker(Tracker):
    """The shipped tracker with step 3 taking ``min_speed`` (heights/s) and ``overrule`` (a vote this strong the other
    way decides) before a clear walk."""

    def __init__(self, min_speed: float = 0.0, overrule: float = np.inf) -> None:
        super().__init__(TrackingConfig())
        self.min_speed, self.overrule = min_speed, overrule

    def _faced(self, person: Person, track: _Track, voted: bool) -> Person:  # shipped _faced, two lines added
        config = self.config

        def not_by_the_walk() -> Person:
            return _by_vote(person, track, config.facing_vote_s) if voted else person

        if len(track.times) < config.min_observations:
            return not_by_the_walk()
        boxes, times = np.array(track.boxes), np.array(track.times)
        feet, height = foot_points(boxes), float((boxes[:, 3] - boxes[:, 1]).sum() / len(boxes))
        speed, error = foot_speed(times, feet[:, 1], height, config.foot_jitter_heights)
        clear = abs(speed) >= config.min_significance * error and abs(speed) >= self.min_speed  # added
        if speed == 0.0 or not (clear or (not voted and abs(person.trusted_handedness) < config.trust_network)):
            return not_by_the_walk()
        if voted and -np.sign(speed) * track.facing_vote(track.times[-1], config.facing_vote_s) <= -self.overrule:
            return not_by_the_walk()  # added: the vote, seen from behind when > 0, reads the walk's other way
        heights = np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)
        growth, _ = foot_speed(times, np.log(heights), 1.0, config.foot_jitter_heights)
        if abs(growth) > config.max_walk_growth_per_s:
            return not_by_the_walk()
        across, _ = foot_speed(times, feet[:, 0], height, config.foot_jitter_heights)
        keypoints = face_ahead(facing_pairs(person, seen_from_behind=speed < 0), float(person.box[3] - person.box[1]),
                               float(np.clip(across / config.profile_speed_heights_per_s, -1.0, 1.0)))
        return replace(person, keypoints=keypoints, facing="motion")


ARMS = {"as shipped": lambda: Tracker(TrackingConfig()),
        "a walk of at least 0.05 heights/s": lambda: CueTracker(min_speed=0.05),
        "a walk of at least 0.1 heights/s": lambda: CueTracker(min_speed=0.1),
        "a walk of at least 0.2 heights/s": lambda: CueTracker(min_speed=0.2),
        "the vote overrules a walk at 0.3": lambda: CueTracker(overrule=0.3),
        "the vote overrules a walk at 0.5": lambda: CueTracker(overrule=0.5),
        "the vote overrules a walk at 0.7": lambda: CueTracker(overrule=0.7)}


if __name__ == "__main__":
    clarity.run(ARMS)
