"""People the frame cuts to a sliver (issue 57, item 3; decision 0031), decoded without retraining: the runtime as
it was against its box laid beyond the edge that cuts a person, and feet beyond the frame owned, on both cameras'
choosing and confirming halves, three compile seeds (frozen experiment).

    git checkout b2a5fbf   # the commit that carried both changes (not kept, and taken out after it)
    cd experiments/2026-11-30-cut-box && PYTHONPATH=../.. python cut_box.py tud B0 B1 B2 -o results/tud
    cd experiments/2026-11-30-cut-box && PYTHONPATH=../.. python cut_box.py pets B0 B1 B2 -o results/pets

Variants (:data:`VARIANTS`), all decoded by the numpy decoder (at b2a5fbf the C decoder decoded the same,
tests/hard_cases/test_native_decode.py):

* ``before``: the box's narrowest width around the centre whatever cuts the person, and feet beyond the frame no
  region's: the runtime of commit aa96de5 (its ``vc.deploy.decode._boxes``, read from git);
* ``feet``: ``before``, with feet beyond the frame moved onto it for the ownership test
  (``vc.deploy.runtime.feet_in_frame``);
* ``edge_box``: ``before``, with the narrowest width laid beyond the map's side edge that a person's mask reaches
  (``vc.deploy.decode._boxes``, step 4);
* ``both``: the two changes.

Writes ``VARIANT/seedS_HALF.json`` per run (AP50 tracked and each frame, recall by the frame's edge, by size and
by overlap, precision); a finished file is not run again. The cameras and halves are
``../2026-11-29-decisions-on-halves/recheck.py``'s.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import subprocess
import sys
import tempfile
import types
from pathlib import Path

import numpy as np

import vc.deploy.decode as decode
import vc.deploy.native as native
import vc.deploy.runtime as runtime
from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)  # its dataclasses look it up there
_RECHECK.loader.exec_module(recheck)
CAMERAS = recheck.CAMERAS
BEFORE = "aa96de5"  # the last commit before decision 0031

BOXES = decode._boxes
FEET_IN_FRAME = runtime.feet_in_frame


def _decoder_before() -> types.ModuleType:
    """``vc/deploy/decode.py`` as it was at :data:`BEFORE`, as a module of its own."""
    source = subprocess.run(["git", "show", f"{BEFORE}:src/vc/deploy/decode.py"], check=True, capture_output=True,
                            text=True, cwd=Path(__file__).parent).stdout
    module = sys.modules["decode_before"] = types.ModuleType("decode_before")  # its dataclasses look it up there
    exec(compile(source, "decode_before.py", "exec"), module.__dict__)
    return module


_OLD_BOXES = _decoder_before()._boxes


def _boxes_before(centres, heights_px, keypoints, owned, mask_columns, width, config, prior=decode.UPRIGHT_PRIOR):
    return _OLD_BOXES(centres, heights_px, keypoints, owned, mask_columns, config, prior)


def _feet_as_decoded(feet: np.ndarray, frame_size: tuple[int, int]) -> np.ndarray:
    return feet


#: variant -> (box rule, feet rule)
VARIANTS = {"before": (_boxes_before, _feet_as_decoded), "feet": (_boxes_before, FEET_IN_FRAME),
            "edge_box": (BOXES, _feet_as_decoded), "both": (BOXES, FEET_IN_FRAME)}


def measure(camera: str, bundle: Path, variant: str, frames: str, output: Path) -> dict:
    spec = CAMERAS[camera]
    request = EvaluationRequest(bundle=bundle, video=spec["video"], ground_truth=spec["gt"], output=output,
                                frames=FrameRange.parse(frames), hog=False, threads=2, tracking=TrackingConfig(),
                                fps=spec["fps"])
    native.default_decoder = lambda: "numpy"
    decode._boxes, runtime.feet_in_frame = VARIANTS[variant]
    try:
        report = evaluate_bundle(request, show_progress=False)
    finally:
        decode._boxes, runtime.feet_in_frame = BOXES, FEET_IN_FRAME
    detectors, misses = report.metrics["detectors"], report.misses
    return {"frames": frames, "ap50_tracked": detectors[OURS]["ap50"],
            "ap50_each_frame": detectors[OURS_SINGLE_FRAME]["ap50"],
            "tracking": report.metrics["tracking"].get("accuracy"),
            "recall_by_edge": misses.recall_by_edge(), "recall_by_height": misses.recall_by_height(),
            "recall_by_group": misses.recall_by_group(), "recall": misses.recall, "precision": misses.precision,
            "false_positives": misses.false_positive_kinds()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(CAMERAS))
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--variants", nargs="*", default=list(VARIANTS))
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    parser.add_argument("--seeds", nargs="*", type=int, help="which of the bundles (default: all)")
    args = parser.parse_args()
    seeds = args.seeds if args.seeds is not None else range(len(args.bundles))
    for half in args.halves:
        for seed in seeds:
            for variant in args.variants:
                path = args.out / variant / f"seed{seed}_{half}.json"
                if path.exists():
                    continue
                with tempfile.TemporaryDirectory() as scratch:
                    result = measure(args.camera, args.bundles[seed], variant,
                                     CAMERAS[args.camera]["halves"][half], Path(scratch))
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(json.dumps(result, indent=1) + "\n")
                edge = result["recall_by_edge"].get("cut by the frame", {})
                print(f"{variant} seed {seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
                      f"{result['ap50_each_frame']:.4f} cut {edge}", flush=True)


if __name__ == "__main__":
    main()
