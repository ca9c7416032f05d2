"""Each tracked person's keypoints averaged with their track's previous frame, within the box (frozen experiment,
issue 57 item 4: pose tracked).

    PYTHONPATH=src python experiments/2026-12-05-keypoints-over-the-track/measure.py CAMERA SEED 0|1 BUNDLE WEIGHT... \
        >> RESULTS/arms.jsonl

A region network reads a person's keypoints frame by frame, and where it is unsure a keypoint jumps between frames
by more than the person moves. Here the tracker's output is post-processed: each keypoint, in the person's box
(x0, y0, width, height of the box), becomes WEIGHT times this frame's plus (1 - WEIGHT) times the track's smoothed
keypoint of the frame before (exponential smoothing; a track unseen in the frame before starts again), after the
tracker has put the pairs in their order. Arms are read in one process with keypoint-model-capacity's ``half()``:
the bundle as shipped (the control, its tracker as is) and one arm per WEIGHT (the same bundle, its own runtime and
tracker, smoothed); the each-frame readings are the same in every arm.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker

_spec = importlib.util.spec_from_file_location(
    "capacity", Path(__file__).parents[1] / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(capacity)


class SmoothingTracker(Tracker):
    """A tracker whose reported people's keypoints are smoothed over their track, in their box."""

    def __init__(self, config, weight: float) -> None:
        super().__init__(config)
        self.weight = weight
        self.smoothed: dict[int, np.ndarray] = {}  # track -> (17, 2) in box units, the frame before
        self.frame = 0

    def update(self, people: list[Person], time_s: float, frame: np.ndarray | None = None) -> list[Person]:
        reported = super().update(people, time_s, frame)
        self.frame += 1
        previous, self.smoothed = self.smoothed, {}
        result = []
        for person in reported:
            x0, y0, x1, y1 = person.box
            size = np.array([max(x1 - x0, 1.0), max(y1 - y0, 1.0)])
            inside = (person.keypoints[:, :2] - [x0, y0]) / size
            if person.track is not None and person.track in previous:
                inside = self.weight * inside + (1.0 - self.weight) * previous[person.track]
            if person.track is not None:
                self.smoothed[person.track] = inside
            keypoints = person.keypoints.copy()
            keypoints[:, :2] = inside * size + [x0, y0]
            result.append(replace(person, keypoints=keypoints))
        return result


def main() -> None:
    camera, seed, which, bundle = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    weights = [float(value) for value in sys.argv[5:]]
    names = ["as shipped"] + [f"weight {weight}" for weight in weights]
    trackers = iter([Tracker] + [lambda config, weight=weight: SmoothingTracker(config, weight) for weight in weights])
    capacity.Tracker = lambda config: next(trackers)(config)  # half() builds the trackers in the arms' order
    first, last, step = capacity.CAMERAS[camera][3][which]
    print(json.dumps({"seed": seed, "camera": camera, "bundle": str(bundle),
                      **capacity.half({name: bundle for name in names}, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
