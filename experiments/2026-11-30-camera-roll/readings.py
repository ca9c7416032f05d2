"""What the scene fitness reads of a camera's roll, on real frames as recorded and rolled (frozen; decision 0026).

    PYTHONPATH=. python experiments/2026-11-30-camera-roll/readings.py BUNDLE --video V --frames 1:400:1 \
        [--rolled-frames 1:400:20] --out FILE.json

Every selected frame as recorded: the roll the halves of its cells read (the fitness's ``roll_deg``) and its state.
The frames of ``--rolled-frames`` rolled about the frame's centre (benchmarks.robustness.roll) by each of ROLLS
degrees: the roll read, the state, and the roll the registration finds."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from benchmarks.robustness import roll
from vc.cores import cpu_facts
from vc.deploy.bundle import load_bundle
from vc.deploy.frames import FrameRange, FrameSource

ROLLS = (0.25, 0.5, 0.75, 1.0, -1.0, 1.5, 2.0, 3.0)


def _spread(values: list[float]) -> dict:
    values = np.asarray(values, np.float64)
    return {"min": round(float(values.min()), 3), "median": round(float(np.median(values)), 3),
            "max": round(float(values.max()), 3)} if values.size else {}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, required=True)
    parser.add_argument("--rolled-frames", type=FrameRange.parse, required=True)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    bundle = load_bundle(args.bundle)
    reference, fit_range = bundle.reference, bundle.fit_range
    recorded = [reference.fitness(frame.image, fit_range) for frame in FrameSource(args.video, args.frames)]
    rolled_frames = [frame.image for frame in FrameSource(args.video, args.rolled_frames)]
    rolls = {}
    for degrees in ROLLS:
        fitness = [reference.fitness(roll(frame, degrees), fit_range) for frame in rolled_frames]
        registered = [reference.register(roll(frame, degrees)) for frame in rolled_frames]
        rolls[f"{degrees:g}"] = {
            "read": _spread([f.roll_deg for f in fitness]),
            "states": {state: sum(f.state == state for f in fitness) for state in sorted({f.state for f in fitness})},
            "registered": _spread([r.roll_deg for r in registered if r is not None]),
            "not registered": sum(r is None for r in registered)}
    report = {"machine": cpu_facts()[0], "bundle": str(args.bundle), "video": str(args.video),
              "frames": len(recorded), "rolled_frames": len(rolled_frames),
              "as recorded": {"read": _spread([f.roll_deg for f in recorded]),
                              "abs read, 99th percentile": round(float(np.percentile(
                                  np.abs([f.roll_deg for f in recorded]), 99)), 3),
                              "states": {state: sum(f.state == state for f in recorded)
                                         for state in sorted({f.state for f in recorded})}},
              "rolled": rolls}
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
