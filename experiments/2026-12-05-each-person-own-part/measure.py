"""One bundle read two ways in one process, frame by frame in turn: people cut from one part of the frame shared by
everyone (the runtime before 0059, the control) and each from their own part (since 0059); pose agreement with
YOLO11n-pose @1280 each frame and tracked, and the time a frame as a ratio, as keypoint-model-capacity measures them
(frozen experiment, decision 0059).

    PYTHONPATH=src python experiments/2026-12-05-each-person-own-part/measure.py CAMERA SEED 0|1 BUNDLE \
        >> RESULTS/arms.jsonl
"""

from __future__ import annotations

import importlib.util
import json
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

import vc.deploy.crop_pose
import vc.deploy.facing
from vc.deploy.facing import frame_part, mirrored
from vc.deploy.runtime import FrameResult, Runtime

_spec = importlib.util.spec_from_file_location(
    "capacity", Path(__file__).parents[1] / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(capacity)
OWN_PARTS = vc.deploy.facing.own_parts


def shared_part(frame: np.ndarray, rois: np.ndarray, mirror: bool = False) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The runtime before 0059: one part of the frame reaching every crop, read in one call."""
    part = frame_part(frame, np.asarray(rois, np.float32).reshape(-1, 4))
    yield mirrored(*part) if mirror else part


class SharedPartRuntime:
    """A runtime whose readers cut everyone from one shared part while it runs a frame (the arms run in turn)."""

    def __init__(self, *args, **kwargs) -> None:
        self.runtime = Runtime(*args, **kwargs)

    def run(self, image: np.ndarray) -> FrameResult:
        vc.deploy.facing.own_parts = vc.deploy.crop_pose.own_parts = shared_part
        try:
            return self.runtime.run(image)
        finally:
            vc.deploy.facing.own_parts = vc.deploy.crop_pose.own_parts = OWN_PARTS

    def close(self) -> None:
        self.runtime.close()


def main() -> None:
    camera, seed, which, bundle = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    arms = iter([SharedPartRuntime, Runtime])  # half() builds the runtimes in the bundles' order: the control first
    capacity.Runtime = lambda *args, **kwargs: next(arms)(*args, **kwargs)
    first, last, step = capacity.CAMERAS[camera][3][which]
    print(json.dumps({"seed": seed, "camera": camera, "bundle": str(bundle),
                      **capacity.half({"shared part": bundle, "own part": bundle}, camera, first, last, step)}),
          flush=True)


if __name__ == "__main__":
    main()
