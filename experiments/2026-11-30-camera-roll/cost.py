"""What reading and undoing a camera's roll costs a frame (frozen; decision record 0026).

    PYTHONPATH=. python experiments/2026-11-30-camera-roll/cost.py BUNDLE --video V --frames 1:400:10 --out FILE.json

On the bundle's scene fitness (its reference): the milliseconds of one core per frame of the fitness as shipped and
with the roll's reading taken out (the halves' four phase correlations), each frame measured both ways in turn,
repeated; a whole frame of the runtime (regions in parallel on 2 threads) as shipped and without the roll's reading,
two runtimes of the bundle timed frame by frame in turn; the view undone for a roll (the gather of every pixel)
against a view only moved (cut and pad); and a registration of a view rolled 1 degree (it runs once per move)."""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path
from statistics import median

from vc.cores import cpu_facts
from vc.deploy.bundle import load_bundle
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.registration import HalvesReference, Registration, _gather_indices, view_back
from vc.deploy.runtime import Runtime

REPEATS = 5


def _ms(function, *arguments) -> float:
    started = time.perf_counter()
    function(*arguments)
    return (time.perf_counter() - started) * 1000.0


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 10))
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    bundle = load_bundle(args.bundle)
    reference, fit_range = bundle.reference, bundle.fit_range
    frames = [frame.image for frame in FrameSource(args.video, args.frames)]
    halves = reference.derived["halves"]
    no_roll = type("NoRoll", (), {"roll": staticmethod(lambda luma, clear_peak: 0.0)})()
    shipped, without = [], []
    for _ in range(REPEATS):
        for frame in frames:
            reference.derived["halves"] = halves
            shipped.append(_ms(reference.fitness, frame, fit_range))
            reference.derived["halves"] = no_roll
            without.append(_ms(reference.fitness, frame, fit_range))
    reference.derived["halves"] = halves
    assert isinstance(halves, HalvesReference)
    with Runtime(args.bundle, threads=2) as shipped_runtime, Runtime(args.bundle, threads=2) as plain_runtime:
        plain_runtime.bundle.reference.derived["halves"] = no_roll
        for frame in frames[:3]:  # warm-up
            shipped_runtime.run(frame), plain_runtime.run(frame)
        runtime = {"as shipped": [], "without": []}
        for index in range(REPEATS * len(frames)):
            frame = frames[index % len(frames)]
            order = [("as shipped", shipped_runtime), ("without", plain_runtime)][::1 if index % 2 else -1]
            for label, each in order:
                runtime[label].append(_ms(each.run, frame))
    rolled, moved = Registration(0, 0, 1.0), Registration(6, -3)
    view_back(frames[0], rolled)  # the gather's indices made once, as a registration in force keeps them
    gather = [_ms(view_back, frame, rolled) for _ in range(REPEATS) for frame in frames]
    cut = [_ms(view_back, frame, moved) for _ in range(REPEATS) for frame in frames]
    _gather_indices.cache_clear()
    indices = [_ms(_gather_indices, *frames[0].shape[:2], Registration(0, 0, 1.0 + k / 100)) for k in range(REPEATS)]
    from benchmarks.robustness import roll

    registering = [_ms(reference.register, roll(frame, 1.0)) for frame in frames[:10]]
    report = {
        "machine": cpu_facts()[0], "python": platform.python_version(), "bundle": str(args.bundle),
        "frames": len(frames), "repeats": REPEATS,
        "fitness_ms": {"as shipped (roll read)": round(median(shipped), 3),
                       "without the roll's reading": round(median(without), 3),
                       "ratio": round(median(shipped) / median(without), 3)},
        "runtime_ms_per_frame": {"as shipped (roll read)": round(median(runtime["as shipped"]), 3),
                                 "without the roll's reading": round(median(runtime["without"]), 3),
                                 "ratio": round(median(runtime["as shipped"]) / median(runtime["without"]), 3)},
        "view_undone_ms": {"rolled 1 degree (gather)": round(median(gather), 3),
                           "moved (6, -3) px (cut and pad)": round(median(cut), 3),
                           "gather indices made, once per registration": round(median(indices), 3)},
        "registration_ms_rolled_1_degree": round(median(registering), 1),
    }
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
