"""A scene's bundles compiled with its people in the default wardrobe (``priors.clothing: mixed``) against the same
scene with ``clothing: winter``, on a camera's choosing and confirming halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure.py CAMERA ARM BUNDLE --seed S -o results     # CAMERA: pets or tud

One ``vc-eval`` evaluation of the bundle on each half, as shipped (the C decoder where built, int8), tracked and
each frame on its own, by ``../2026-12-01-tud-denser-crowd/measure.py``'s measurement pointed at the camera (the
halves and rates are ``../2026-11-29-decisions-on-halves/recheck.py``'s). Writes
``results/CAMERA_ARM/seedS_HALF.json``; a finished file is not run again. Pose agreement is
``../2026-12-02-keypoint-model-capacity/measure.py``'s.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

_CROWD = importlib.util.spec_from_file_location(
    "crowd_measure", Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd" / "measure.py")
crowd_measure = sys.modules["crowd_measure"] = importlib.util.module_from_spec(_CROWD)
_CROWD.loader.exec_module(crowd_measure)
recheck = crowd_measure.recheck


def measure(camera: str, bundle: Path, frames: str, output: Path) -> dict:
    """``crowd_measure.measure``, which reads TUD-Stadtmitte, pointed at ``camera``."""
    crowd_measure.TUD = recheck.CAMERAS[camera]
    return crowd_measure.measure(bundle, frames, output)


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
