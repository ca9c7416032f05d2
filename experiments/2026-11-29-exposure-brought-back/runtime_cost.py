"""What bringing a frame's exposure back costs the runtime (frozen experiment, issue 62): PETS09 frames as recorded,
under COCO-C's brightness (severity 3: read +1.4 to +1.7 stops, brought back and run) and under its snow (read
overexposed, brought back, judged changed otherwise and withheld), through ``Runtime.run`` with the bundle as
shipped, each run as a camera gives it (its frames one after the other: the correction is kept from frame to
frame), the three in turn in one process, a few rounds, each also with the reach set to 0 (no frame brought back,
0017's runtime); the median milliseconds a frame each, and their ratios to a frame as recorded.

    python experiments/2026-11-29-exposure-brought-back/runtime_cost.py BUNDLE [--frames 20] [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from benchmarks.robustness import coco_c_conditions, condition_seed
from vc.cores import cpu_facts
from vc.deploy import exposure
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

VIDEO = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "pets09_s2l1" / "vtest.avi"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    frames = [frame.image for frame in FrameSource(VIDEO, FrameRange(1, 400, 400 // args.frames))][:args.frames]
    brightness, snow = coco_c_conditions(["brightness", "snow"], [3])
    variants = {"as recorded": frames,
                "brightness 3 (brought back, run)": [brightness.transform(frame, condition_seed(brightness.key, str(i)))
                                                     for i, frame in enumerate(frames)],
                "snow 3 (brought back, withheld)": [snow.transform(frame, condition_seed(snow.key, str(i)))
                                                    for i, frame in enumerate(frames)]}
    reaches = {"": exposure.REACH_STOPS, ", reach 0": 0.0}
    names = [name + reach for name in variants for reach in reaches]
    times: dict[str, list[float]] = {name: [] for name in names}
    states: dict[str, dict[str, int]] = {name: {} for name in names}
    with Runtime(args.bundle, threads=args.threads) as runtime:
        for frame in frames[:3]:
            runtime.run(frame)  # warm up
        for _ in range(args.rounds):
            for name, images in variants.items():
                for reach_name, reach in reaches.items():
                    exposure.REACH_STOPS = reach
                    for image in images:
                        started = time.perf_counter()
                        result = runtime.run(image)
                        times[name + reach_name].append(1000 * (time.perf_counter() - started))
                        key = result.fitness.state + (" brought back" if result.fitness.exposure_corrected_stops
                                                      is not None else "")
                        states[name + reach_name][key] = states[name + reach_name].get(key, 0) + 1
    base = float(np.median(times["as recorded"]))
    report = {"machine": cpu_facts()[0], "threads": args.threads, "frames": len(frames), "rounds": args.rounds,
              "median_ms": {name: round(float(np.median(values)), 2) for name, values in times.items()},
              "ratio_to_as_recorded": {name: round(float(np.median(values)) / base, 3)
                                       for name, values in times.items()},
              "states": states}
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
