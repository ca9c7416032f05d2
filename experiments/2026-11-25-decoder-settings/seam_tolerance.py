"""How far across a seam a region keeps a person whose feet it puts in a neighbour's owned area
(:data:`vc.deploy.runtime.SEAM_FOOT_TOLERANCE`), on real frames: one bundle's heat maps are computed once, then the
frames are reported under each tolerance as the runtime reports them; real AP50 each frame and the miss analysis
(:func:`decode_variants.measure`).

    python experiments/2026-11-25-decoder-settings/seam_tolerance.py BUNDLE --video V --gt GT.txt
        [--frames 1:400:5 | --all-frames] [--tolerance 0 0.05 0.1 0.2]
        --out experiments/2026-11-25-decoder-settings/results

Writes ``seam_tolerance.json`` to ``--out`` and prints one line per tolerance. Tracking is left out (``vc-eval``
measures the bundle tracked, at the shipped tolerance).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from decode_variants import heatmaps_of, measure

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import SEAM_FOOT_TOLERANCE, Runtime
from vc.evaluation.mot import read_mot_boxes
from vc.io import write_json


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    frames = parser.add_mutually_exclusive_group()
    frames.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 5))
    frames.add_argument("--all-frames", action="store_true", help="every frame of the video or folder")
    parser.add_argument("--tolerance", type=float, nargs="+", default=[0.0, 0.05, 0.1, 0.2],
                        help="person heights (0: a region keeps only its own area, as before the tolerance)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    source = FrameSource(args.video) if args.all_frames else FrameSource(args.video, args.frames)
    runtime = Runtime(args.bundle, parallel_regions=False)
    truth = read_mot_boxes(args.gt)
    numbers, maps = heatmaps_of(runtime, source)
    results = {}
    for tolerance in args.tolerance:
        results[str(tolerance)] = measure(runtime, numbers, maps, truth, {}, seam_tolerance=tolerance)
        overlap = results[str(tolerance)].get("recall_by_overlap", {}).get("overlapping another", {})
        print(f"tolerance {tolerance:<5} AP50 {results[str(tolerance)]['ap50']:.4f}  "
              f"recall overlapping {overlap.get('recall', float('nan')):.3f}")
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "seam_tolerance.json", {"bundle": str(args.bundle), "video": str(args.video),
                                                  "frames": "all" if args.all_frames else str(args.frames),
                                                  "shipped": SEAM_FOOT_TOLERANCE,
                                                  "tolerances": results})
    print(json.dumps({"written": str(args.out)}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
