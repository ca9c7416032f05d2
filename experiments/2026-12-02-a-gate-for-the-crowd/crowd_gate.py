"""A wider association gate only where nobody else could be the match: does it keep PETS09's identities at its real
rate (0046) without losing TUD-Stadtmitte's crowd? IDF1, AP50 tracked and pose agreement tracked, both halves
(frozen; identities-at-the-real-rate's lead).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted:experiments/2026-12-02-identities-at-the-real-rate \
        python experiments/2026-12-02-a-gate-for-the-crowd/crowd_gate.py BUNDLE SEED CAMERA >> results/arms.jsonl

identities-at-the-real-rate found wider gates (0.25 heights, or 2.5 heights a second) keep PETS09's identities better
and lose on TUD-Stadtmitte, where people walk closer together than a wider gate allows for. Here a person may continue
a track from beyond the shipped gate (0.15 heights + 1.5 heights a second) up to a wider one only where the pair is
alone within the wider gate: no other live track is predicted that near the person, and no other person of the frame
is that near the track. In a crowd the shipped gate holds. Each arm is the shipped tracker (main at 40c8917) with its
association so changed; the frame loop and scoring are gates.py's (its ``ARMS`` and ``Tracker`` replaced here).
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

import arms as voted  # experiments/2026-12-02-small-people-voted/arms.py: data and halves
import gates  # experiments/2026-12-02-identities-at-the-real-rate/gates.py: the frame loop and scoring
import numpy as np

from vc.deploy.boxes import foot_points
from vc.deploy.tracking import Tracker, TrackingConfig, _Track, appearance_distance


@dataclass(frozen=True)
class Arm:
    """The shipped settings, and the wider gate an unambiguous pair may use (None: the shipped association)."""

    wide_gate_heights: float | None = None
    wide_speed_heights_per_s: float = 1.5
    everywhere: bool = False  # the wider gate for every pair (identities-at-the-real-rate's arms), for comparison


ARMS = {"as shipped": Arm(),
        "0.25 heights + 2.5 a second where alone": Arm(0.25, 2.5),
        "0.25 heights where alone": Arm(0.25, 1.5),
        "0.15 heights + 2.5 a second where alone": Arm(0.15, 2.5),
        "0.35 heights + 3 a second where alone": Arm(0.35, 3.0),
        "0.25 heights + 2.5 a second everywhere": Arm(0.25, 2.5, everywhere=True)}


class CrowdGateTracker(Tracker):
    """The shipped tracker, whose step 1 lets a pair beyond the gate up to ``arm``'s wider one where it is alone."""

    def __init__(self, arm: Arm) -> None:
        super().__init__(TrackingConfig())
        self.arm = arm

    def _associate(self, people, tracks, time_s, start_new, looks, predicted):
        if self.arm.wide_gate_heights is None:
            return super()._associate(people, tracks, time_s, start_new, looks, predicted)
        config, arm = self.config, self.arm
        boxes = np.array([p.box for p in people], np.float64).reshape(-1, 4)
        feet, heights = foot_points(boxes), np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)

        def reach(candidates: list[_Track]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            expected = np.array([predicted[id(t)] for t in candidates], np.float64).reshape(-1, 2)
            unseen = time_s - np.array([t.times[-1] for t in candidates], np.float64)
            distances = np.hypot(feet[:, None, 0] - expected[None, :, 0],
                                 feet[:, None, 1] - expected[None, :, 1]) / heights[:, None]
            return (distances, config.gate_heights + config.max_speed_heights_per_s * unseen,
                    arm.wide_gate_heights + arm.wide_speed_heights_per_s * unseen)

        distances, narrow, wide = reach(tracks)
        within_wide = distances <= wide[None, :]
        if arm.everywhere:
            allowed = within_wide
        else:
            all_distances, _, all_wide = reach([t for t in self.tracks if id(t) in predicted])  # every live track
            tracks_near_person = (all_distances <= all_wide[None, :]).sum(axis=1)
            people_near_track = within_wide.sum(axis=0)
            alone = (tracks_near_person[:, None] <= 1) & (people_near_track[None, :] <= 1)
            allowed = (distances <= narrow[None, :]) | (within_wide & alone)
        rows, columns = np.nonzero(allowed)
        costs = distances[rows, columns]
        for k, (i, j) in enumerate(zip(rows.tolist(), columns.tolist(), strict=True)):
            look, track_look = looks.get(id(people[i])), tracks[j].appearance
            if look is not None and track_look is not None:
                costs[k] += config.appearance_weight * appearance_distance(look, track_look)
        assigned: dict[int, _Track] = {}
        taken: set[int] = set()
        for k in np.lexsort((columns, rows, costs)).tolist():
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


def main() -> None:
    gates.ARMS, gates.Tracker = ARMS, CrowdGateTracker
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    for name, (first, last, step) in zip(voted.HALVES, voted.DATA[camera][3], strict=True):
        readings = gates.half(bundle, camera, first, last, step)
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "frames": [first, last, step], **readings}), flush=True)


if __name__ == "__main__":
    main()
