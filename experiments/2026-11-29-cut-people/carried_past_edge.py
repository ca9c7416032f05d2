"""Tracks carried past the frame's edge (frozen experiment, issue 57, item 3): with boxes clipped to the frame
(0020, the runtime at commit 1b78550), the tracker still carries a person it lost for up to 0.5 s at their walking
velocity, and one walking out is carried beyond the edge. Variants of the tracker's carried people:

- ``runtime_0020``: as the tracker is;
- ``carried_within``: a carried person whose feet leave the frame is dropped, the others' boxes clipped to it.

    python experiments/2026-11-29-cut-people/carried_past_edge.py tud BUNDLE0 BUNDLE1 BUNDLE2 -o results/tud

Writes ``VARIANT/seedS_HALF.json`` as ``edge_variants.py`` does (its evaluation, with the runtime left as it is).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from vc.deploy import tracking

_EDGE = importlib.util.spec_from_file_location("edge_variants", Path(__file__).parent / "edge_variants.py")
edge = sys.modules["edge_variants"] = importlib.util.module_from_spec(_EDGE)
_EDGE.loader.exec_module(edge)


def carried_within(frame_size: tuple[int, int]):
    """The tracker's step 5, then its people kept to the frame."""
    original = tracking.Tracker._carried
    width, height = frame_size
    low, high = np.array([-0.5, -0.5, -0.5, -0.5]), np.array([width - 0.5, height - 0.5] * 2)

    def within(self, unseen, seen_boxes, time_s):
        kept = []
        for person in original(self, unseen, seen_boxes, time_s):
            foot_x, foot_y = (person.box[0] + person.box[2]) / 2, person.box[3]
            if -0.5 <= foot_x <= width - 0.5 and foot_y <= height - 0.5 + 0.1 * (person.box[3] - person.box[1]):
                person.box = np.minimum(np.maximum(person.box, low), high)
                kept.append(person)
        return kept

    return within


VARIANTS = {"runtime_0020": None, "carried_within": carried_within}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(edge.CAMERAS))
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp())
    original = tracking.Tracker._carried
    for variant, patch in VARIANTS.items():
        for seed, bundle in enumerate(args.bundles):
            for half, frames in edge.CAMERAS[args.camera]["halves"].items():
                target = args.out / variant / f"seed{seed}_{half}.json"
                if target.exists():
                    continue
                if patch is not None:
                    tracking.Tracker._carried = patch(edge.FRAME_SIZES[args.camera])
                try:
                    result = edge.measure(args.camera, bundle, "as_shipped", frames,
                                          scratch / variant / str(seed) / half)
                finally:
                    tracking.Tracker._carried = original
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_text(json.dumps({"variant": variant, "seed": seed, "half": half,
                                              "bundle": str(bundle), **result}, indent=1))
                cut = result["recall_by_edge"].get("cut by the frame", {})
                print(f"{variant:14s} seed {seed} {half:10s} tracked {result['ap50_tracked']:.3f} MOTA "
                      f"{result['tracking']['mota']:.3f} cut {cut.get('recall')} ({cut.get('people')})", flush=True)


if __name__ == "__main__":
    main()
