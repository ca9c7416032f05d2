"""The tracker's settings for people it carries through frames that miss them and for weak people continuing a
track, chosen on all 400 of PETS09's dev frames (experiments/2026-11-25-tracking), each moved on its own on the
choosing and confirming halves; and whether carried people covered by someone seen should be dropped more readily
(frozen experiment, issue 57 items 1 and 2).

    PYTHONPATH=../../src python measure.py CAMERA SEED BUNDLE [--variants NAME ...] --label COMPILE \
        >> results/CAMERA.jsonl

Each run is ``vc-eval``'s evaluation of the bundle on one half (``../2026-12-01-tud-denser-crowd/measure.py``'s
measurement, the halves and rates of ``../2026-11-29-decisions-on-halves/recheck.py``), tracked with the variant's
settings (:data:`VARIANTS`).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

import vc.deploy.tracking as tracking
from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)
_RECHECK.loader.exec_module(recheck)

#: name -> (TrackingConfig fields changed, or share of a carried box that a seen person's box covers that also makes
#: it a duplicate, or None)
VARIANTS: dict[str, tuple[dict, float | None]] = {
    "shipped": ({}, None),
    **{f"iou_{value}": ({"coast_duplicate_iou": value}, None) for value in (0.4, 0.5, 0.6, 0.8, 0.9)},
    "never": ({"coast_duplicate_iou": 1.01}, None),
    **{f"covered_{value}": ({}, value) for value in (0.8, 0.9)},
    **{f"coast_{value}s": ({"coast_s": value}, None) for value in (0.3, 0.8, 1.2)},
    **{f"seen_{value}": ({"coast_min_observations": value}, None) for value in (2, 5)},
    **{f"decay_{value}s": ({"coast_score_decay_s": value}, None) for value in (0.5, 2.0)},
    **{f"weak_{value}": ({"weak_people_above": value}, None) for value in (0.05, 0.15)},
    "coast_1.2s_never": ({"coast_s": 1.2, "coast_duplicate_iou": 1.01}, None),
    "coast_0.8s_iou_0.9": ({"coast_s": 0.8, "coast_duplicate_iou": 0.9}, None),
    "coast_1.2s_iou_0.9": ({"coast_s": 1.2, "coast_duplicate_iou": 0.9}, None),
    "coast_1.2s_iou_0.8": ({"coast_s": 1.2, "coast_duplicate_iou": 0.8}, None),
    "coast_1.0s_iou_0.8": ({"coast_s": 1.0, "coast_duplicate_iou": 0.8}, None),
}


def covered_or_iou(covered: float):
    """A stand-in for ``box_iou`` in the tracker's step 5 that also calls a carried box a duplicate where a seen
    person's box covers at least ``covered`` of it: it returns the IoU, or where the covered share passes, 1."""
    def overlap(box: np.ndarray, seen: np.ndarray) -> np.ndarray:
        box, seen = np.asarray(box, np.float64).reshape(1, 4), np.asarray(seen, np.float64).reshape(-1, 4)
        width = np.clip(np.minimum(box[:, 2], seen[:, 2]) - np.maximum(box[:, 0], seen[:, 0]), 0, None)
        height = np.clip(np.minimum(box[:, 3], seen[:, 3]) - np.maximum(box[:, 1], seen[:, 1]), 0, None)
        own = max((box[0, 2] - box[0, 0]) * (box[0, 3] - box[0, 1]), 1e-9)
        share = width * height / own
        return np.where(share[None] >= covered, 1.0, box_iou(box, seen))
    return overlap


def measure(camera: str, bundle: Path, half: str, variant: str) -> dict:
    fields, covered = VARIANTS[variant]
    settings = recheck.CAMERAS[camera]
    tracking.box_iou = covered_or_iou(covered) if covered is not None else box_iou
    try:
        with tempfile.TemporaryDirectory() as scratch:
            request = EvaluationRequest(bundle=bundle, video=settings["video"], ground_truth=settings["gt"],
                                        output=Path(scratch), frames=FrameRange.parse(settings["halves"][half]),
                                        hog=False, threads=2,
                                        tracking=replace(TrackingConfig(), **fields),
                                        fps=settings["fps"])
            report = evaluate_bundle(request, show_progress=False)
    finally:
        tracking.box_iou = box_iou
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
