"""People whose decoded feet fall just beyond the outer edge of the regions' areas, kept (frozen experiment).

    PYTHONPATH=../../src python edge.py CAMERA ARM BUNDLE --seed S -o results     # ARM: today or edge

``edge``: a region keeps a person whose feet it puts in no region's owned area within SEAM_FOOT_TOLERANCE box
heights of its own, as it keeps those just across a seam. Writes ``results/CAMERA_ARM/seedS_HALF.json``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

import vc.deploy.runtime as runtime

_SPEC = importlib.util.spec_from_file_location(
    "winter_measure", Path(__file__).parent.parent / "2026-12-04-winter-clothing" / "measure.py")
winter_measure = sys.modules["winter_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(winter_measure)
_ACROSS = runtime.just_across_seam


class _Beyond:
    """The area of every foot point no region owns: ``contains`` is true outside all ``areas``."""

    def __init__(self, areas):
        self.areas = areas

    def contains(self, points):
        return ~np.any([area.contains(points) for area in self.areas], axis=0)


def across_or_beyond(feet, heights, area, neighbour_areas, tolerance=runtime.SEAM_FOOT_TOLERANCE):
    """``just_across_seam``, the ground beyond every region's area counted as one more neighbour."""
    return _ACROSS(feet, heights, area, (*neighbour_areas, _Beyond((area, *neighbour_areas))), tolerance)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=("pets", "tud"))
    parser.add_argument("arm", choices=("today", "edge"))
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    if args.arm == "edge":
        runtime.just_across_seam = across_or_beyond
    halves = winter_measure.recheck.CAMERAS[args.camera]["halves"]
    for half in args.halves:
        path = args.out / f"{args.camera}_{args.arm}" / f"seed{args.seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = winter_measure.measure(args.camera, args.bundle, halves[half], Path(scratch))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{args.camera} {args.arm} seed {args.seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
              f"{result['ap50_each_frame']:.4f} groups {result['recall_by_group']} fp {result['false_positives']}",
              flush=True)


if __name__ == "__main__":
    main()
