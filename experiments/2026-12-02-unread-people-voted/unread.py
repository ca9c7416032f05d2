"""Should a person the facing model did not read this frame (a weak person continuing a track, decoded below the
centre threshold for the tracker's eyes only) face the way their track's vote reads them? Pose agreement with
YOLO11n-pose @1280 tracked, both halves (frozen, issue 57).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-walk-clarity \
        python experiments/2026-12-02-unread-people-voted/unread.py BUNDLE SEED CAMERA >> results/arms.jsonl

The runtime reads only the people above the centre threshold with the facing model (vc.deploy.runtime
Runtime.faced); weak people keep the networks' order, and the tracker (main at 92e0912) orders them by their walk,
clear or not, unless the networks are confident. Their track may hold the model's readings of the frames they were
seen strongly. The arm lets those readings vote for them as for anyone read (0044, 0047, 0049). Each frame runs once
through the bundle as shipped; every arm's tracker is fed a copy of its people (walk-clarity's ``half``).
"""

from __future__ import annotations

import clarity  # experiments/2026-12-02-walk-clarity/clarity.py: the frame loop and scoring

from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker, TrackingConfig, _Track


class VotingForUnread(Tracker):
    """The shipped tracker, with the track's vote standing for a person the model did not read where it has one."""

    def _faced(self, person: Person, track: _Track, voted: bool) -> Person:
        has_vote = track.facing_vote(track.times[-1], self.config.facing_vote_s) != 0.0
        return super()._faced(person, track, voted or has_vote)


ARMS = {"as shipped": lambda: Tracker(TrackingConfig()),
        "the track's vote for people the model did not read": lambda: VotingForUnread(TrackingConfig())}


if __name__ == "__main__":
    clarity.run(ARMS)
