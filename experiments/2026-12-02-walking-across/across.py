"""Should the walk decide the facing of a person walking across the view, whose feet barely move toward or away from
the camera? Pose agreement with YOLO11n-pose @1280 tracked, both halves (frozen, issue 57).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-walk-clarity \
        python experiments/2026-12-02-walking-across/across.py BUNDLE SEED CAMERA >> results/arms.jsonl

The walk reads a person seen from behind where their feet move up the image, from the front where they move down
(vc.deploy.tracking, step 3). Someone crossing the view is seen in profile, and their small motion up or down the
image may be clear and still say little about which side faces the camera. Each arm is the shipped tracker (main at
f1250d4) in which a person the facing model read, whose feet move across the image at least K times as fast as up
or down it, is ordered by the track's vote instead of the walk (K = 1, 2, 4). Same bundles, frame loop and scoring as
walk-clarity (``clarity.half``).
"""

from __future__ import annotations

import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring
import numpy as np

from vc.deploy.boxes import foot_points
from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker, TrackingConfig, _by_vote, _Track, foot_speed


class AcrossTracker(Tracker):
    """The shipped tracker, whose step 3 leaves a read person crossing the view ``ratio`` times faster than they
    move up or down it to the track's vote."""

    def __init__(self, ratio: float) -> None:
        super().__init__(TrackingConfig())
        self.ratio = ratio

    def _faced(self, person: Person, track: _Track, voted: bool) -> Person:
        config = self.config
        if voted and len(track.times) >= config.min_observations:
            boxes, times = np.array(track.boxes), np.array(track.times)
            feet, height = foot_points(boxes), float((boxes[:, 3] - boxes[:, 1]).mean())
            speed, _ = foot_speed(times, feet[:, 1], height, config.foot_jitter_heights)
            across, _ = foot_speed(times, feet[:, 0], height, config.foot_jitter_heights)
            if abs(across) >= self.ratio * abs(speed):
                return _by_vote(person, track, config.facing_vote_s)
        return super()._faced(person, track, voted)


ARMS = {"as shipped": lambda: Tracker(TrackingConfig()),
        "the vote for people crossing as fast as they come or go": lambda: AcrossTracker(1.0),
        "the vote for people crossing twice as fast": lambda: AcrossTracker(2.0),
        "the vote for people crossing four times as fast": lambda: AcrossTracker(4.0)}


if __name__ == "__main__":
    clarity.run(ARMS)
