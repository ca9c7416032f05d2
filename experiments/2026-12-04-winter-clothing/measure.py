"""A scene's bundles compiled with its people in the default wardrobe (``priors.clothing: mixed``) against the same
scene with ``clothing: winter``, on a camera's choosing and confirming halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure.py CAMERA ARM BUNDLE --seed S -o results     # CAMERA: pets or tud

One ``vc-eval`` evaluation of the bundle on each half, as shipped (the C decoder where built, int8), tracked and
each frame on its own, as ``../2026-12-01-tud-denser-crowd/measure.py`` measures TUD-Stadtmitte (the halves and
rates are ``../2026-11-29-decisions-on-halves/recheck.py``'s). Writes ``results/CAMERA_ARM/seedS_HALF.json``; a
finished file is not run again. Pose agreement is ``../2026-12-02-keypoint-model-capacity/measure.py``'s.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)  # its dataclasses look it up there
_RECHECK.loader.exec_module(recheck)


def measure(camera: str, bundle: Path, frames: str, output: Path) -> dict:
    spec = recheck.CAMERAS[camera]
    request = EvaluationRequest(bundle=bundle, video=spec["video"], ground_truth=spec["gt"], output=output,
                                frames=FrameRange.parse(frames), hog=False, threads=2, tracking=TrackingConfig(),
                                fps=spec["fps"])
    report = evaluate_bundle(request, show_progress=False)
    detectors, misses = report.metrics["detectors"], report.misses
    return {"frames": frames, "ap50_tracked": detectors[OURS]["ap50"],
            "ap50_each_frame": detectors[OURS_SINGLE_FRAME]["ap50"],
            "ms_each_frame": detectors[OURS_SINGLE_FRAME]["ms_per_frame"]["median"],
            "tracking": report.metrics["tracking"].get("accuracy"),
            "recall_by_group": misses.recall_by_group(), "recall_by_height": misses.recall_by_height(),
            "recall_by_region": misses.recall_by_region(), "recall_by_edge": misses.recall_by_edge(),
            "recall": misses.recall, "precision": misses.precision, "false_positives": misses.false_positive_kinds()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(recheck.CAMERAS))
    parser.add_argument("arm")
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    for half in args.halves:
        path = args.out / f"{args.camera}_{args.arm}" / f"seed{args.seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = measure(args.camera, args.bundle, recheck.CAMERAS[args.camera]["halves"][half], Path(scratch))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{args.camera} {args.arm} seed {args.seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
              f"{result['ap50_each_frame']:.4f} groups {result['recall_by_group']}", flush=True)


if __name__ == "__main__":
    main()
