"""TUD-Stadtmitte's scene with a denser crowd in its renders (issue 57, item 2; decision 0032): bundles compiled from
the scene as docs/results.md makes it (``priors: {m2_per_person: 10, group_rate: 0.3}``) against the same scene at
``m2_per_person: 5``, three compile seeds each, on the choosing and confirming halves (frozen experiment).

    PYTHONPATH=../.. python measure.py ARM B0 B1 B2 -o results      # ARM: crowd_10 or crowd_5

Each run is ``vc-eval``'s evaluation of one bundle on one half, as shipped (the C decoder where built, int8),
tracked and each frame on its own. Writes ``results/ARM/seedS_HALF.json``; a finished file is not run again. The
halves are ``../2026-11-29-decisions-on-halves/recheck.py``'s.
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
TUD = recheck.CAMERAS["tud"]


def measure(bundle: Path, frames: str, output: Path) -> dict:
    request = EvaluationRequest(bundle=bundle, video=TUD["video"], ground_truth=TUD["gt"], output=output,
                                frames=FrameRange.parse(frames), hog=False, threads=2, tracking=TrackingConfig(),
                                fps=TUD["fps"])
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
    parser.add_argument("arm")
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--seeds", nargs="*", type=int, help="which of the bundles (default: all)")
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    for half in args.halves:
        for seed in args.seeds if args.seeds is not None else range(len(args.bundles)):
            path = args.out / args.arm / f"seed{seed}_{half}.json"
            if path.exists():
                continue
            with tempfile.TemporaryDirectory() as scratch:
                result = measure(args.bundles[seed], TUD["halves"][half], Path(scratch))
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(result, indent=1) + "\n")
            print(f"{args.arm} seed {seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
                  f"{result['ap50_each_frame']:.4f} groups {result['recall_by_group']}", flush=True)


if __name__ == "__main__":
    main()
