"""Whether a carried box overlapping a person seen at the same depth (their feet level with its own) should be
dropped as that person's duplicate, while one behind a nearer seen person is carried on (frozen experiment,
issue 57 item 2).

    PYTHONPATH=../../src python measure.py CAMERA SEED BUNDLE --label COMPILE [--variants NAME ...] \
        [--halves choosing] >> results/CAMERA.jsonl

Each run is ``../2026-12-05-carried-people/measure.py``'s measurement (``vc-eval``'s, on one half), the tracker's
step 5 replaced by :class:`DepthAwareTracker` with the variant's settings (:data:`VARIANTS`).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

import vc.evaluation.real_video as real_video
from vc.deploy.boxes import box_iou, foot_points
from vc.deploy.frames import FrameRange
from vc.deploy.runtime import Person
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)
_RECHECK.loader.exec_module(recheck)


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
    fields, rule = VARIANTS[variant]
    settings = recheck.CAMERAS[camera]
    real_video.Tracker = depth_aware(rule) if rule is not None else Tracker
    try:
        with tempfile.TemporaryDirectory() as scratch:
            request = EvaluationRequest(bundle=bundle, video=settings["video"], ground_truth=settings["gt"],
                                        output=Path(scratch), frames=FrameRange.parse(settings["halves"][half]),
                                        hog=False, threads=2, tracking=replace(TrackingConfig(), **fields),
                                        fps=settings["fps"])
            report = evaluate_bundle(request, show_progress=False)
    finally:
        real_video.Tracker = Tracker
    detectors, misses = report.metrics["detectors"], report.misses
    return {"ap50_tracked": detectors[OURS]["ap50"], "ap50_each_frame": detectors[OURS_SINGLE_FRAME]["ap50"],
            "tracking": report.metrics["tracking"].get("accuracy"),
            "recall_by_group": misses.recall_by_group(), "recall_by_height": misses.recall_by_height(),
            "recall": misses.recall, "precision": misses.precision, "false_positives": misses.false_positive_kinds()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(recheck.CAMERAS))
    parser.add_argument("seed", type=int)
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--variants", nargs="*", default=list(VARIANTS))
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    parser.add_argument("--label", default="", help="which compile the bundle is, written with each line")
    args = parser.parse_args()
    for half in args.halves:
        for variant in args.variants:
            result = measure(args.camera, args.bundle, half, variant)
            print(json.dumps({"camera": args.camera, "seed": args.seed, "compile": args.label, "half": half,
                              "variant": variant, **result}), flush=True)


if __name__ == "__main__":
    main()
