"""docs/results.md's real-frame figures from compiles of the scenes exactly as they ship (frozen experiment,
issue 57): each bundle on both halves, as ``../2026-12-04-winter-clothing/measure.py`` measures them.

    PYTHONPATH=../../src python measure.py CAMERA BUNDLE --seed S      # CAMERA: pets or tud

Writes ``results/CAMERA/seedS_HALF.json``; a finished file is not run again. Pose agreement is
``../2026-12-02-keypoint-model-capacity/measure.py``'s (README, Method).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

_WINTER = importlib.util.spec_from_file_location(
    "winter_measure", Path(__file__).parent.parent / "2026-12-04-winter-clothing" / "measure.py")
winter_measure = sys.modules["winter_measure"] = importlib.util.module_from_spec(_WINTER)
_WINTER.loader.exec_module(winter_measure)
recheck = winter_measure.recheck

RESULTS = Path(__file__).parent / "results"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(recheck.CAMERAS))
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    args = parser.parse_args()
    for half in ("choosing", "confirming"):
        path = RESULTS / args.camera / f"seed{args.seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = winter_measure.measure(args.camera, args.bundle, recheck.CAMERAS[args.camera]["halves"][half],
                                            Path(scratch))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{args.camera} seed {args.seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
              f"{result['ap50_each_frame']:.4f}", flush=True)


if __name__ == "__main__":
    main()
