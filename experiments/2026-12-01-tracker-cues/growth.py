"""Does the box's growth tell a walker coming toward the camera from one going away better than the feet's motion?
The tracker as shipped against variants that read approach from the log box height's slope: alone, where the feet's
motion is unclear, only where both agree, or whichever is more significant (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-tracker-cues/growth.py BUNDLE tud|pets [HALF] \
        >> experiments/2026-12-01-tracker-cues/results/growth.jsonl
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from common import DATA, scored_half

from vc.deploy.boxes import foot_points
from vc.deploy.facing import face_ahead
from vc.deploy.tracking import Tracker, TrackingConfig, facing_pairs, foot_speed

MODES = ("shipped", "growth", "growth_if_feet_unclear", "both_agree", "stronger")


class Variant(Tracker):
    def __init__(self, mode: str) -> None:
        super().__init__(TrackingConfig())
        self.mode = mode

    def _faced(self, person, track):
        if self.mode == "shipped":
            return super()._faced(person, track)
        config = self.config
        if len(track.times) < config.min_observations:
            return person
        boxes, times = np.array(track.boxes), np.array(track.times)
        feet, height = foot_points(boxes), float((boxes[:, 3] - boxes[:, 1]).sum() / len(boxes))
        speed, error = foot_speed(times, feet[:, 1], height, config.foot_jitter_heights)
        growth, growth_error = foot_speed(times, np.log(np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)), 1.0,
                                          config.foot_jitter_heights)
        if abs(growth) > config.max_walk_growth_per_s:
            return person
        feet_clear = speed != 0.0 and abs(speed) >= config.min_significance * error
        growth_clear = growth != 0.0 and abs(growth) >= config.min_significance * growth_error
        unsure = abs(person.trusted_handedness) < config.trust_network
        if self.mode == "growth":
            if growth == 0.0 or not (growth_clear or unsure):
                return person
            behind = growth < 0
        elif self.mode == "growth_if_feet_unclear":
            if feet_clear or (unsure and not growth_clear and speed != 0.0):
                behind = speed < 0
            elif growth_clear:
                behind = growth < 0
            else:
                return person
        elif self.mode == "both_agree":
            if not (feet_clear and growth_clear and (speed < 0) == (growth < 0)):
                return person
            behind = speed < 0
        else:  # stronger
            feet_z = abs(speed) / error if speed else 0.0
            growth_z = abs(growth) / growth_error if growth else 0.0
            if (max(feet_z, growth_z) < config.min_significance and not unsure) or feet_z == growth_z == 0.0:
                return person
            behind = (speed < 0) if feet_z >= growth_z else (growth < 0)
        across, _ = foot_speed(times, feet[:, 0], height, config.foot_jitter_heights)
        keypoints = face_ahead(facing_pairs(person, seen_from_behind=behind), float(person.box[3] - person.box[1]),
                               float(np.clip(across / config.profile_speed_heights_per_s, -1.0, 1.0)))
        return replace(person, keypoints=keypoints, facing="motion")


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    halves = DATA[camera][3] if len(sys.argv) < 4 else [DATA[camera][3][int(sys.argv[3])]]
    for first, last, step in halves:
        readings = scored_half(bundle, camera, first, last, step, {mode: Variant(mode) for mode in MODES})
        print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": [first, last, step], **readings}),
              flush=True)


if __name__ == "__main__":
    main()
