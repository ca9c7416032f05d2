"""One bundle's people (tracked, as vc-eval tracks) and YOLO11n-pose @1280's on one half, kept for ``pairs.py``
(frozen experiment, issue 57 item 4: which of a person's left/right pairs are read the other way round).

    PYTHONPATH=../../src python collect.py CAMERA HALF BUNDLE OUT.pkl      # CAMERA: pets or tud; HALF: 0 or 1

Frames and scoring as ``../2026-12-02-keypoint-model-capacity/measure.py``.
"""

from __future__ import annotations

import importlib.util
import pickle
import sys
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.mot import read_mot_boxes

_SPEC = importlib.util.spec_from_file_location(
    "capacity_measure", Path(__file__).parent.parent / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(capacity)
ROOT = Path(__file__).parent.parent.parent


def collect(camera: str, which: int, bundle: Path) -> list[dict]:
    video, gt, fps, halves = capacity.CAMERAS[camera]
    first, last, step = halves[which]
    truth = read_mot_boxes(ROOT / gt)
    reference = YoloPoseOnnx(ROOT / capacity.REFERENCE, threads=2)
    runtime = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    tracker = Tracker(TrackingConfig())
    frames = []
    try:
        for frame in FrameSource(ROOT / video, FrameRange(first, last, 1)):
            result = runtime.run(frame.image)
            each = [p.to_dict() for p in result.people if not p.weak]
            tracked = result.reported(tracker.update(result.people, frame.number / fps, frame.image))
            if (frame.number - first) % step:
                continue
            seen = reference(frame.image)
            frames.append({"frame": frame.number, "truth": truth.get(frame.number, np.zeros((0, 4))),
                           "ours": [p.to_dict() for p in tracked], "each": each,
                           "theirs": {"boxes": seen.boxes, "scores": seen.scores, "keypoints": seen.keypoints}})
    finally:
        runtime.close()
    return frames


if __name__ == "__main__":
    camera, which, bundle, out = sys.argv[1], int(sys.argv[2]), Path(sys.argv[3]), Path(sys.argv[4])
    out.write_bytes(pickle.dumps(collect(camera, which, bundle)))
