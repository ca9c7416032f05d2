"""Milliseconds per real frame of several bundles timed frame by frame in one process: each frame is run by every
bundle in turn, the order rotated from frame to frame, regions in parallel.

    python -m benchmarks.runtime_interleaved LABEL=BUNDLE LABEL=BUNDLE [...] --video V [--frames 1:400:5]
        [--threads 2] [--passes 4] [--out FILE.json]

The first bundle is the reference. Timed in one process, frame by frame, the bundles share the drift of a shared
machine's speed: it slows every bundle alike within a few frames, so the ratios hold even when the absolute times
do not, where bundles timed in separate processes must be alternated to compare
(``experiments/2026-11-27-input-size/results/input_mixed_pets09.md``). Reports the median of each bundle's frame
times, their ratio to the reference's, and the median of the per-frame ratios (the two differ where a bundle's frame
times spread: the regions' threads of a bundle finishing close together make a frame whichever of them is late).
Prints one JSON line; with ``--out`` appends it to that file.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from benchmarks import display_path
from vc.cores import cpu_facts
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.errors import InputError

WARM_UP_FRAMES = 3


def interleaved_seconds(bundles: list[Path], frames: list[np.ndarray], threads: int,
                        passes: int) -> np.ndarray:
    """(len(bundles), passes * len(frames)) seconds of each bundle's runtime, regions in parallel on ``threads``
    (:func:`timed_in_turn`)."""
    runtimes = [Runtime(bundle, threads=threads, parallel_regions=True) for bundle in bundles]
    try:
        return timed_in_turn(runtimes, frames, passes)
    finally:
        for runtime in runtimes:
            runtime.close()


def timed_in_turn(runtimes: Sequence[Callable[[np.ndarray], object]], frames: list[np.ndarray],
                  passes: int) -> np.ndarray:
    """(len(runtimes), passes * len(frames)) seconds of runtimes already made (any callable on a frame: a bundle's
    runtime with settings of its own, another decoder say), each warmed up on the first frames: column k is one
    frame run by every runtime, in an order rotated by one from column to column so that no runtime always runs
    first after another's frame."""
    for runtime in runtimes:
        for frame in frames[:WARM_UP_FRAMES]:
            runtime(frame)
    seconds = np.zeros((len(runtimes), passes * len(frames)))
    for column in range(passes * len(frames)):
        frame = frames[column % len(frames)]
        for step in range(len(runtimes)):
            which = (column + step) % len(runtimes)
            started = time.perf_counter()
            runtimes[which](frame)
            seconds[which, column] = time.perf_counter() - started
    return seconds


def summary(labels: list[str], seconds: np.ndarray) -> dict:
    """Medians in milliseconds, their ratios to the first bundle's, and the median of the per-frame ratios."""
    medians = np.median(seconds, axis=1)
    return {"median_ms": {label: round(float(m) * 1e3, 2) for label, m in zip(labels, medians, strict=True)},
            "ratio_of_medians": {label: round(float(m / medians[0]), 3) for label, m in zip(labels, medians,
                                                                                           strict=True)},
            "median_of_frame_ratios": {label: round(float(np.median(row / seconds[0])), 3)
                                       for label, row in zip(labels, seconds, strict=True)}}


def report(result: dict, out: Path | None) -> None:
    """Prints ``result`` as one JSON line and, with ``out``, appends that line to it (runs accumulate in one file)."""
    line = json.dumps(result)
    print(line)
    if out is not None:
        with out.open("a") as file:
            file.write(line + "\n")


def _labelled(text: str) -> tuple[str, Path]:
    label, separator, path = text.partition("=")
    if not separator or not label or not path:
        raise argparse.ArgumentTypeError(f"{text!r}: expected LABEL=BUNDLE")
    return label, Path(path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundles", type=_labelled, nargs="+", metavar="LABEL=BUNDLE")
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 5))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--passes", type=int, default=4)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    labels, paths = [label for label, _ in args.bundles], [path for _, path in args.bundles]
    if len(set(labels)) != len(labels):
        parser.error("each bundle needs its own label")
    try:
        frames = [frame.image for frame in FrameSource(args.video, args.frames)]
        for path in paths:  # a bundle that does not load is bad input, said before any timing
            Runtime(path).close()
    except InputError as error:
        parser.error(str(error))
    seconds = interleaved_seconds(paths, frames, args.threads, args.passes)
    result = {"machine": cpu_facts()[0], "bundles": dict(zip(labels, map(display_path, paths), strict=True)),
              "video": display_path(args.video), "frames": len(frames), "passes": args.passes,
              "threads": args.threads, **summary(labels, seconds)}
    report(result, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
