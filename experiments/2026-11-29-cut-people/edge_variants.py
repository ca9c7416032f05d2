"""People cut by the frame's edge (issue 57, item 3), decoded without retraining: the bundles as shipped against
variants of the runtime, on both cameras' choosing and confirming halves, three compile seeds (frozen experiment).

    python experiments/2026-11-29-cut-people/edge_variants.py pets BUNDLE0 BUNDLE1 BUNDLE2 -o results/pets
    python experiments/2026-11-29-cut-people/edge_variants.py tud BUNDLE0 BUNDLE1 BUNDLE2 -o results/tud

Variants (:data:`VARIANTS`): ``clipped``, every person's box clipped to the frame, as annotators draw a person
the frame cuts. Writes ``VARIANT/seedS_HALF.json`` per run (AP50 tracked and each frame, recall by the frame's
edge); a finished file is not run again. The cameras, halves and evaluation are
``../2026-11-29-decisions-on-halves/recheck.py``'s.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

import vc.deploy.runtime as runtime
from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)  # its dataclasses look it up there
_RECHECK.loader.exec_module(recheck)
CAMERAS = recheck.CAMERAS
FRAME_SIZES = {"pets": (768, 576), "tud": (640, 480)}


def clipped_boxes(frame_size: tuple[int, int]) -> Callable:
    """The runtime's last step on a person, then the box clipped to the frame (pixel centres at integers)."""
    original = runtime.moved_by
    width, height = frame_size
    low, high = np.array([-0.5, -0.5, -0.5, -0.5]), np.array([width - 0.5, height - 0.5] * 2)

    def moved_and_clipped(person, shift):
        person = original(person, shift)
        person.box = np.minimum(np.maximum(person.box, low), high).astype(person.box.dtype)
        return person

    return moved_and_clipped


VARIANTS = {"as_shipped": None, "clipped": clipped_boxes}


def measure(camera: str, bundle: Path, variant: str, frames: str, output: Path) -> dict:
    spec = CAMERAS[camera]
    request = EvaluationRequest(bundle=bundle, video=spec["video"], ground_truth=spec["gt"], output=output,
                                frames=FrameRange.parse(frames), hog=False, threads=2, tracking=TrackingConfig(),
                                fps=spec["fps"])
    original = runtime.moved_by
    if VARIANTS[variant] is not None:
        runtime.moved_by = VARIANTS[variant](FRAME_SIZES[camera])
    try:
        report = evaluate_bundle(request, show_progress=False)
    finally:
        runtime.moved_by = original
    detectors, misses = report.metrics["detectors"], report.misses
    return {"frames": frames, "ap50_tracked": detectors[OURS]["ap50"],
            "ap50_each_frame": detectors[OURS_SINGLE_FRAME]["ap50"],
            "tracking": report.metrics["tracking"].get("accuracy"),
            "recall_by_edge": misses.recall_by_edge(), "recall": misses.recall, "precision": misses.precision,
            "near_miss_box_errors": misses.near_miss_errors()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(CAMERAS))
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--variants", nargs="*", default=list(VARIANTS))
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp())  # vc-eval's images and reports: the numbers kept are the JSON below
    for variant in args.variants:
        for seed, bundle in enumerate(args.bundles):
            for half, frames in CAMERAS[args.camera]["halves"].items():
                target = args.out / variant / f"seed{seed}_{half}.json"
                if target.exists():
                    continue
                result = measure(args.camera, bundle, variant, frames, scratch / variant / str(seed) / half)
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_text(json.dumps({"variant": variant, "seed": seed, "half": half,
                                              "bundle": str(bundle), **result}, indent=1))
                cut = result["recall_by_edge"].get("cut by the frame", {})
                print(f"{variant:12s} seed {seed} {half:10s} tracked {result['ap50_tracked']:.3f} each frame "
                      f"{result['ap50_each_frame']:.3f} cut {cut.get('recall')} ({cut.get('people')})", flush=True)


if __name__ == "__main__":
    main()
