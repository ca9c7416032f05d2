"""What the veil, noise and view-correlation measurements cost a frame (frozen experiment, issue 62): the runtime
with today's scene fitness and with the fitness as decision 0014 shipped it (commit c08fe69, read from git) on PETS09
dev frames as recorded, and the two fitness measurements alone on those frames and under fog (a veil today's takes
off; 0014's found the frame changed and the runtime ran no network on it), interleaved in one process (the ratio
holds on a shared machine whose speed drifts).

    python experiments/2026-11-29-weather-and-gain/runtime_cost.py BUNDLE VIDEO --out OUT.json [--frames 1:400:10]
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import json
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from imagecorruptions import corrupt

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

#: The commit whose fitness is the baseline: the last before the weather and gain ranges.
BASELINE = "c08fe69"


def _baseline_fitness():
    """The fitness module as :data:`BASELINE` had it, imported from a temporary file."""
    source = subprocess.run(["git", "show", f"{BASELINE}:src/vc/deploy/fitness.py"], check=True,
                            capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "fitness_0014.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("fitness_0014", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["fitness_0014"] = module
    spec.loader.exec_module(module)
    return module


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
    runtimes = {"0014": Runtime(args.bundle, threads=args.threads), "today": Runtime(args.bundle, threads=args.threads)}
    old = _baseline_fitness()
    reference = runtimes["today"].bundle.reference
    old_reference = old.SceneReference(reference.cells, reference.decode, reference.cell_px, reference.fine_rows)
    old_range = old.FitRange(**{field.name: getattr(runtimes["today"].bundle.fit_range, field.name)
                                for field in dataclasses.fields(old.FitRange)})
    runtimes["0014"].bundle = dataclasses.replace(runtimes["0014"].bundle, reference=old_reference,
                                                  fit_range=old_range)
    conditions = {"as recorded": frames, "fog 2": [corrupt(frame, corruption_name="fog", severity=2)
                                                   for frame in frames]}
    measurements = {"0014": (old_reference, old_range), "today": (reference, runtimes["today"].bundle.fit_range)}
    runtime_ms: dict[str, list[float]] = {setting: [] for setting in runtimes}
    fitness_ms = {name: {setting: [] for setting in measurements} for name in conditions}
    for runtime in runtimes.values():
        runtime.run(frames[0])  # warm-up
    for _ in range(args.rounds):
        for frame in frames:
            for setting, runtime in runtimes.items():
                started = time.perf_counter()
                runtime.run(frame)
                runtime_ms[setting].append((time.perf_counter() - started) * 1e3)
        for name, chosen in conditions.items():
            for frame in chosen:
                for setting, (measured_against, fit_range) in measurements.items():
                    started = time.perf_counter()
                    measured_against.fitness(frame, fit_range)
                    fitness_ms[name][setting].append((time.perf_counter() - started) * 1e3)
    report = {"bundle": args.bundle.name, "frames": args.frames, "rounds": args.rounds, "threads": args.threads,
              "machine": platform.processor() or platform.machine(), "runtime_ms_per_frame": {}, "fitness_ms": {}}
    before, after = (float(np.median(runtime_ms[setting])) for setting in runtimes)
    report["runtime_ms_per_frame"]["as recorded"] = {"fitness of 0014": round(before, 2), "today": round(after, 2),
                                                     "ratio": round(after / before, 3)}
    print(f"runtime, as recorded: {before:.2f} ms with 0014's fitness, {after:.2f} ms today ({after / before:.3f}x)")
    for name, measured in fitness_ms.items():
        before, after = (float(np.median(measured[setting])) for setting in measurements)
        report["fitness_ms"][name] = {"0014": round(before, 2), "today": round(after, 2),
                                      "ratio": round(after / before, 3)}
        print(f"fitness, {name}: {before:.2f} ms in 0014, {after:.2f} ms today ({after / before:.3f}x)")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
