"""Milliseconds per real frame of one bundle under the runtime code of this checkout: regions in parallel and in
turn, median over the frames (each seen ``--repeats`` times, after a warm-up of three).

    python experiments/2026-11-27-runtime-per-frame/runtime_frame_time.py BUNDLE --video V [--frames 1:400:5]
        [--threads 2] [--repeats 2] [--label NAME]
        [--out experiments/2026-11-27-runtime-per-frame/results/runtime_areas.jsonl]

Where ``benchmarks/runtime_latency.py`` compares two bundles, this compares two versions of the runtime on one
bundle: run it at one commit and at another, alternately and twice each on the same machine, and compare the
ratios (results/runtime_areas.md). Prints one JSON line; with ``--out`` appends it to that file.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import time
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.errors import InputError


def frame_milliseconds(bundle: Path, frames: list[np.ndarray], parallel: bool, threads: int, repeats: int) -> float:
    with Runtime(bundle, threads=threads, parallel_regions=parallel) as runtime:
        for frame in frames[:3]:
            runtime(frame)
        times = []
        for _ in range(repeats):
            for frame in frames:
                started = time.perf_counter()
                runtime(frame)
                times.append(time.perf_counter() - started)
    return round(float(np.median(times)) * 1e3, 2)


def report(result: dict, out: Path | None) -> None:
    """Prints ``result`` as one JSON line and, with ``out``, appends that line to it (runs accumulate in one file)."""
    line = json.dumps(result)
    print(line)
    if out is not None:
        with out.open("a") as file:
            file.write(line + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 5))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--label", default=None, help="what to call this measurement (default: the commit)")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    try:
        frames = [frame.image for frame in FrameSource(args.video, args.frames)]
        Runtime(args.bundle).close()  # a bundle that does not load is bad input, said before any timing
    except InputError as error:
        parser.error(str(error))
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=Path(__file__).resolve().parent).stdout.strip()
    result = {"label": args.label or commit, "commit": commit, "bundle": str(args.bundle), "frames": len(frames),
              "threads": args.threads,
              "parallel_ms": frame_milliseconds(args.bundle, frames, True, args.threads, args.repeats),
              "in_turn_ms": frame_milliseconds(args.bundle, frames, False, args.threads, args.repeats)}
    report(result, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
