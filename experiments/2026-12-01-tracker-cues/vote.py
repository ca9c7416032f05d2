"""Two more uses of a track for pose, against the tracker as shipped: where the walk does not decide, the facing
model's readings summed over the track's last seconds order the pairs (a vote); and each person's keypoints, in
their box's frame, smoothed over the track with a time constant (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-tracker-cues/vote.py BUNDLE tud|pets [HALF] \
        >> experiments/2026-12-01-tracker-cues/results/vote.jsonl
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from common import DATA, scored_half

from vc.deploy.tracking import Tracker, TrackingConfig, facing_pairs

VARIANTS = {"shipped": {}, "vote0.5": {"vote_s": 0.5}, "vote1": {"vote_s": 1.0}, "vote3": {"vote_s": 3.0},
            "smooth.04": {"smooth_tau": 0.04}, "smooth.08": {"smooth_tau": 0.08}, "smooth.15": {"smooth_tau": 0.15}}


class Variant(Tracker):
    def __init__(self, vote_s: float = 0.0, smooth_tau: float = 0.0) -> None:
        super().__init__(TrackingConfig())
        self.vote_s, self.smooth_tau = vote_s, smooth_tau
        self.votes: dict[int, list[tuple[float, float]]] = {}
        self.smoothed: dict[int, tuple[float, np.ndarray]] = {}

    def _faced(self, person, track):
        now = track.times[-1]
        if self.vote_s and person.pair_handedness is not None:
            kept = [(t, v) for t, v in self.votes.get(track.identity, []) if t > now - self.vote_s]
            self.votes[track.identity] = [*kept, (now, float(np.mean(person.pair_handedness)))]
        out = super()._faced(person, track)
        if self.vote_s and out.facing != "motion" and person.pair_handedness is not None:
            total = sum(v for _, v in self.votes[track.identity])
            if total != 0.0:
                out = replace(out, keypoints=facing_pairs(out, seen_from_behind=total > 0))
        if self.smooth_tau:
            box = out.box
            size = np.array([max(box[2] - box[0], 1.0), max(box[3] - box[1], 1.0)])
            relative = (out.keypoints[:, :2] - box[:2]) / size
            before = self.smoothed.get(track.identity)
            if before is not None and now - before[0] < 0.2:
                relative = before[1] + (1 - np.exp(-(now - before[0]) / self.smooth_tau)) * (relative - before[1])
            self.smoothed[track.identity] = (now, relative)
            keypoints = out.keypoints.copy()
            keypoints[:, :2] = box[:2] + relative * size
            out = replace(out, keypoints=keypoints)
        return out


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    halves = DATA[camera][3] if len(sys.argv) < 4 else [DATA[camera][3][int(sys.argv[3])]]
    for first, last, step in halves:
        readings = scored_half(bundle, camera, first, last, step,
                               {name: Variant(**kwargs) for name, kwargs in VARIANTS.items()})
        print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": [first, last, step], **readings}),
              flush=True)


if __name__ == "__main__":
    main()
