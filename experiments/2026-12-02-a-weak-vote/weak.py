"""Where the walk is unclear and the facing model's vote over the track is weak, which decides: the vote, or the
walk's sign as before 0047? Pose agreement with YOLO11n-pose @1280 tracked, both halves (frozen, issue 57).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-walk-clarity \
        python experiments/2026-12-02-a-weak-vote/weak.py BUNDLE SEED CAMERA >> results/arms.jsonl

Who-is-swapped found the vote wrong for a third of the small PETS09 people it orders. Each arm is the shipped tracker
(main at 6038544) in which a person whose track's vote is weaker than V (of 1) is faced as a person the model did not
read: by an unclear walk's sign unless the networks are confident (V = 0.1, 0.2, 0.3). Same bundles, frame loop and
scoring as walk-clarity (``clarity.half``).
"""

from __future__ import annotations

import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring

from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker, TrackingConfig, _Track


class WeakVoteTracker(Tracker):
    """The shipped tracker, in which a vote weaker than ``least`` does not count as one."""

    def __init__(self, least: float) -> None:
        super().__init__(TrackingConfig())
        self.least = least

    def _faced(self, person: Person, track: _Track, voted: bool) -> Person:
        strong = abs(track.facing_vote(track.times[-1], self.config.facing_vote_s)) >= self.least
        return super()._faced(person, track, voted and strong)


ARMS = {"as shipped": lambda: Tracker(TrackingConfig()),
        "a vote under 0.1 does not count": lambda: WeakVoteTracker(0.1),
        "a vote under 0.2 does not count": lambda: WeakVoteTracker(0.2),
        "a vote under 0.3 does not count": lambda: WeakVoteTracker(0.3)}


if __name__ == "__main__":
    clarity.run(ARMS)
