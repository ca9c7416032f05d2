"""What the tone normalisation costs a frame (frozen experiment, issue 62): PETS09 dev frames as recorded and two
stops darker, the runtime with and without ``normalise_tone``, interleaved in one process (the ratio holds on a
shared machine whose speed drifts).

    python experiments/2026-11-29-tone-normalisation/runtime_cost.py BUNDLE VIDEO [--frames 1:400:10] [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime


def darker(frame: np.ndarray, reference, stops: float) -> np.ndarray:
    """``frame`` with ``stops`` less light through the bundle's camera response."""
    table = reference.decode.astype(np.float64)
    light = table[frame] * 2.0 ** stops
    return np.clip(np.rint(np.interp(light, table, np.arange(256.0))), 0, 255).astype(np.uint8)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("bundle", type=Path)
    parser.add_argument("video", type=Path)
    parser.add_argument("--frames", default="1:400:10")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    frames = [frame.image for frame in FrameSource(args.video, FrameRange.parse(args.frames))]
    runtimes = {setting: Runtime(args.bundle, threads=args.threads, normalise_tone=setting)
                for setting in (False, True)}
    reference = runtimes[True].bundle.reference
    conditions = {"as recorded": frames, "-2 stops": [darker(frame, reference, -2.0) for frame in frames]}
    times: dict[str, dict[bool, list[float]]] = {name: {False: [], True: []} for name in conditions}
    for runtime in runtimes.values():
        runtime.run(frames[0])  # warm-up
    for _ in range(args.rounds):
        for name, chosen in conditions.items():
            for frame in chosen:
                for setting, runtime in runtimes.items():
                    started = time.perf_counter()
                    runtime.run(frame)
                    times[name][setting].append((time.perf_counter() - started) * 1e3)
    report = {"bundle": args.bundle.name, "frames": args.frames, "rounds": args.rounds, "threads": args.threads,
              "machine": platform.processor() or platform.machine(), "ms_per_frame": {}}
    for name, measured in times.items():
        without, with_tone = (float(np.median(measured[setting])) for setting in (False, True))
        report["ms_per_frame"][name] = {"as given": round(without, 2), "normalised": round(with_tone, 2),
                                        "ratio": round(with_tone / without, 3)}
        print(f"{name}: {without:.2f} ms as given, {with_tone:.2f} ms normalised ({with_tone / without:.3f}x)")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
