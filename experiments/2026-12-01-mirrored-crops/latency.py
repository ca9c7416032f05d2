"""What reading tall people twice costs a frame: one bundle run by the runtime reading every crop once, by the runtime
as it ships (its facing model reads people 100 px and taller twice, their crop and its mirror), with the keypoint
model reading them twice too, and with the keypoint model alone reading them twice; frame by frame in one process,
the order rotated from frame to frame (as benchmarks/runtime_interleaved.py times bundles; frozen).

    PYTHONPATH=src python experiments/2026-12-01-mirrored-crops/latency.py BUNDLE CAMERA \
        >> experiments/2026-12-01-mirrored-crops/results/latency.jsonl

Run at cc5023a, the commit that made the facing model read tall people twice (decision 0042): its runtime reads the
facing model's crops as it ships, the keypoint model's once; the keypoint model reading twice is this experiment's
(arms.py). From 8bcd139 on, the runtime's keypoint model reads each crop twice itself (decision 0043).
"""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
from arms import MirroredCropPose  # the same folder's: the keypoint model's maps averaged with its mirror's

from vc.deploy.facing import FacingReader, FacingReading, crop_rois, frame_part, front_logits
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import TrackingConfig

FRAMES = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", FrameRange(1, 400, 5)),
          "tud": ("../shared/data/tud_stadtmitte/frames", FrameRange(1, 179, 1))}
PASSES, WARM_UP = 2, 3


class OnceFacing(FacingReader):
    """The facing model reading every crop once, as before decision 0042."""

    def read(self, frame: np.ndarray, boxes: np.ndarray) -> FacingReading:
        if not len(boxes):
            return super().read(frame, boxes)
        boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
        found = self._outputs(*frame_part(frame, crop_rois(boxes)))
        return FacingReading(front_logits(found["front_logit"], found.get("head_front_logit"),
                                          boxes[:, 3] - boxes[:, 1]), found.get("face_across"))


def runtimes(bundle: Path) -> dict[str, Runtime]:
    """The runtime reading every crop once, as it ships (the facing model reading tall people twice), and with the
    keypoint model reading them twice beside either."""
    weak = TrackingConfig().weak_people_above
    runs = {}
    for name, facing_once, crop_twice in (("read once", True, False), ("facing read twice", False, False),
                                          ("keypoints read twice", True, True), ("tall people read twice", False,
                                                                                 True)):
        run = Runtime(bundle, threads=2, weak_people_above=weak)
        threads = 1 if run.pool is not None else 2  # as the runtime gives each region's sessions
        for runner in run.runners:
            if facing_once and runner.facing is not None:
                runner.facing = OnceFacing(run.bundle.facing, threads)
            if crop_twice and runner.crop_pose is not None:
                runner.crop_pose = MirroredCropPose(run.bundle.crop_pose, threads)
        runs[name] = run
    return runs


def main() -> None:
    bundle, camera = Path(sys.argv[1]), sys.argv[2]
    video, frames = FRAMES[camera]
    images = [frame.image for frame in FrameSource(Path(video), frames)]
    runs = runtimes(bundle)
    names = list(runs)
    seconds = {name: [] for name in names}
    try:
        for image in images[:WARM_UP]:
            for run in runs.values():
                run.run(image)
        for column in range(PASSES * len(images)):
            for step in range(len(names)):
                name = names[(column + step) % len(names)]
                started = time.perf_counter()
                runs[name].run(images[column % len(images)])
                seconds[name].append(time.perf_counter() - started)
    finally:
        for run in runs.values():
            run.close()
    medians = {name: float(np.median(values)) for name, values in seconds.items()}
    print(json.dumps({"bundle": str(bundle), "camera": camera, "frames": len(images), "passes": PASSES,
                      "machine": f"{platform.processor() or platform.machine()}, 2 threads",
                      "median_ms": {name: round(1e3 * value, 2) for name, value in medians.items()},
                      "ratio": {name: round(value / medians["read once"], 3) for name, value in medians.items()},
                      "median_of_frame_ratios": {name: round(float(np.median(np.array(values) /
                                                                             np.array(seconds["read once"]))), 3)
                                                 for name, values in seconds.items()}}))


if __name__ == "__main__":
    main()
