"""What taking a veil off costs the runtime (frozen experiment, issue 62): PETS09 frames as recorded and under
COCO-C's contrast at severities 4 (read ``dark``) and 5 (read ``covered``), through ``Runtime.run`` with the bundle as
shipped, each run as a camera gives it (consecutive frames, one after the other: the tables are kept from frame to
frame while they differ by at most KEPT_TABLE_CODES; frames further apart often differ more, and the networks then
run twice: ``--step 10``),
in turn in one process, a few rounds, each also with the veil path off (the frames withheld, as before it); the
median milliseconds a frame each, and their ratios to a frame as recorded.

    python experiments/2026-11-29-veil-taken-off/runtime_cost.py BUNDLE [--frames 20] [--rounds 3] [--step 1]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import vc.deploy.runtime as runtime_module
from benchmarks.robustness import coco_c_conditions, condition_seed
from vc.cores import cpu_facts
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.veil import veiled

VIDEO = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "pets09_s2l1" / "vtest.avi"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--step", type=int, default=1, help="frames between those run (1: as a camera gives them)")
    args = parser.parse_args()
    frames = [frame.image for frame in FrameSource(VIDEO, FrameRange(101, 400, args.step))][:args.frames]
    variants = {"as recorded": frames}
    for condition in coco_c_conditions(["contrast"], [4, 5]):
        variants[condition.key] = [condition.transform(frame, condition_seed(condition.key, str(index)))
                                   for index, frame in enumerate(frames)]
    paths = {"": veiled, ", veil path off": lambda fitness: False}
    names = [name + path for name in variants for path in paths]
    times: dict[str, list[float]] = {name: [] for name in names}
    states: dict[str, dict[str, int]] = {name: {} for name in names}
    with Runtime(args.bundle, threads=args.threads) as runtime:
        for frame in frames[:3]:
            runtime.run(frame)  # warm up
        for _ in range(args.rounds):
            for name, images in variants.items():
                for path_name, path in paths.items():
                    runtime_module.veiled = path
                    for image in images:
                        started = time.perf_counter()
                        result = runtime.run(image)
                        times[name + path_name].append(1000 * (time.perf_counter() - started))
                        key = result.fitness.state + (" veil taken off" if result.fitness.veil_taken_off
                                                      is not None else "")
                        states[name + path_name][key] = states[name + path_name].get(key, 0) + 1
    base = float(np.median(times["as recorded"]))
    report = {"machine": cpu_facts()[0], "threads": args.threads, "frames": len(frames), "step": args.step,
              "rounds": args.rounds,
              "median_ms": {name: round(float(np.median(values)), 2) for name, values in times.items()},
              "ratio_to_as_recorded": {name: round(float(np.median(values)) / base, 3)
                                       for name, values in times.items()},
              "states": states}
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
