"""How many of PETS09's scored people the rule of decision 0044 can reach, from the ground truth alone (frozen): people
100 px and taller whose walk over the tracker's window, read from their own annotated boxes, is not clear (or not a
walk, or too short a track), on the frames vc-eval scores (every 5th). No PETS09 bundle was compiled this session.

    PYTHONPATH=src python experiments/2026-12-02-facing-over-the-track/pets_exposure.py > results/pets_exposure.txt
"""

from __future__ import annotations

import numpy as np

from vc.deploy.facing import MIRRORED_FROM_PX
from vc.deploy.tracking import TrackingConfig, foot_speed

GROUND_TRUTH = "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"
FPS = 7.0
HALVES = {"choosing": (1, 200), "confirming": (201, 400)}


def walk_is_clear(history: np.ndarray, config: TrackingConfig) -> bool:
    """The tracker's test of a walk, on a person's annotated rows (frame, id, left, top, width, height) in its
    window."""
    if len(history) < config.min_observations:
        return False
    times, heights = history[:, 0] / FPS, history[:, 5]
    speed, error = foot_speed(times, history[:, 3] + heights, float(heights.mean()), config.foot_jitter_heights)
    growth, _ = foot_speed(times, np.log(heights), 1.0, config.foot_jitter_heights)
    return speed != 0.0 and abs(speed) >= config.min_significance * error and \
        abs(growth) <= config.max_walk_growth_per_s


def main() -> None:
    config, rows = TrackingConfig(), np.loadtxt(GROUND_TRUTH, delimiter=",")
    for half, (first, last) in HALVES.items():
        scored = rows[np.isin(rows[:, 0], np.arange(first, last + 1, 5))]
        tall = scored[scored[:, 5] >= MIRRORED_FROM_PX]
        unclear = sum(not walk_is_clear(rows[(rows[:, 1] == person[1]) & (rows[:, 0] <= person[0])
                                             & (rows[:, 0] >= person[0] - FPS * config.window_s)], config)
                      for person in tall)
        print(f"{half}: {len(scored)} people scored, {len(tall)} of them 100 px and taller, "
              f"{unclear} of those with a walk that is not clear")


if __name__ == "__main__":
    main()
