"""Whether a carried box overlapping a person seen at the same depth (their feet level with its own) should be
dropped as that person's duplicate, while one behind a nearer seen person is carried on (frozen experiment,
issue 57 item 2).

    PYTHONPATH=../../src python measure.py CAMERA SEED BUNDLE --label COMPILE [--variants NAME ...] \
        [--halves choosing] >> results/CAMERA.jsonl

Each run is ``../2026-12-05-carried-people/measure.py``'s measurement and command line (``vc-eval``'s, on one half),
the tracker's step 5 replaced by :class:`DepthAwareTracker` with the variant's settings (:data:`VARIANTS`).
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import vc.evaluation.real_video as real_video
from vc.deploy.boxes import box_iou, foot_points
from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker

_CARRIED = importlib.util.spec_from_file_location(
    "carried_measure", Path(__file__).parent.parent / "2026-12-05-carried-people" / "measure.py")
carried = sys.modules["carried_measure"] = importlib.util.module_from_spec(_CARRIED)
_CARRIED.loader.exec_module(carried)


@dataclass(frozen=True)
class SameDepth:
    """A carried box overlapping a seen person's above ``iou`` is dropped as a duplicate where that person's feet
    lie less than ``feet_heights`` (of the carried box's height) below its own: they stand no nearer to the camera,
    so they cannot be hiding it."""

    iou: float
    feet_heights: float


#: name -> (TrackingConfig fields changed, the same-depth rule or None)
VARIANTS: dict[str, tuple[dict, SameDepth | None]] = {
    "shipped": ({}, None),
    "coast_1.0s_iou_0.8": ({"coast_s": 1.0, "coast_duplicate_iou": 0.8}, None),
    **{f"coast_1.0s_iou_0.8_depth_{iou}_{feet}": ({"coast_s": 1.0, "coast_duplicate_iou": 0.8}, SameDepth(iou, feet))
       for iou in (0.4, 0.5, 0.6) for feet in (0.1, 0.15, 0.2)},
    **{f"depth_{iou}_{feet}": ({}, SameDepth(iou, feet)) for iou in (0.4, 0.5) for feet in (0.1, 0.15, 0.2)},
}


def depth_aware(rule: SameDepth):
    """A :class:`Tracker` whose step 5 also drops carried boxes that a seen person at the same depth overlaps."""

    class DepthAwareTracker(Tracker):
        def update(self, people, time_s, frame=None):
            result = super().update(people, time_s, frame)
            seen = np.array([p.box for p in result if not p.coasted], np.float64).reshape(-1, 4)
            return [p for p in result if not (p.coasted and len(seen) and self._same_depth(p, seen))]

        @staticmethod
        def _same_depth(person: Person, seen: np.ndarray) -> bool:
            overlaps = box_iou(person.box[None], seen)[0]
            height = max(float(person.box[3] - person.box[1]), 1.0)
            feet_below = (foot_points(seen)[:, 1] - foot_points(person.box[None])[0, 1]) / height
            return bool(np.any((overlaps > rule.iou) & (feet_below < rule.feet_heights)))

    return DepthAwareTracker


def measure(camera: str, bundle: Path, half: str, variant: str) -> dict:
    """``carried-people``'s measurement with the variant's tracker settings and, where it has one, its rule."""
    fields, rule = VARIANTS[variant]
    carried.VARIANTS[variant] = (fields, None)
    real_video.Tracker = depth_aware(rule) if rule is not None else Tracker
    try:
        return _carried_measure(camera, bundle, half, variant)
    finally:
        real_video.Tracker = Tracker


_carried_measure = carried.measure
carried.measure = measure  # carried-people's command line, over this experiment's variants
carried.VARIANTS = {name: (fields, None) for name, (fields, _) in VARIANTS.items()}

if __name__ == "__main__":
    carried.main()
