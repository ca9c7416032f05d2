"""What a frame costs with the keypoint model at int8 reading each crop twice, against the bundle as shipped before
it (fp32, each crop once): two runtimes in one process, frame by frame, the order rotated from frame to frame, two
passes (as benchmarks/runtime_interleaved.py times bundles; frozen).

    PYTHONPATH=<a79b13d..cc5023a>/src python experiments/2026-12-01-int8-crop-models/latency.py CONTROL INT8_BUNDLE \
        >> experiments/2026-12-01-int8-crop-models/results/latency.jsonl

Run on code that reads each crop of the keypoint model once (cc5023a); the arm's second reading is
../2026-12-01-mirrored-crops/arms.py's MirroredCropPose.
"""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
from arms import MIRRORED, runtime  # the same folder's

from vc.deploy.frames import FrameRange, FrameSource

PASSES, WARM_UP = 2, 3


def main() -> None:
    control, int8 = Path(sys.argv[1]), Path(sys.argv[2])
    images = [frame.image for frame in FrameSource(Path(MIRRORED.DATA["tud"][0]), FrameRange(1, 179, 1))]
    runs = {"fp32, each crop once": runtime(control, False), "int8, each crop twice": runtime(int8, True)}
    names = list(runs)
    seconds: dict[str, list[float]] = {name: [] for name in names}
    try:
        for image in images[:WARM_UP]:
            for run in runs.values():
                run.run(image)
        for column in range(PASSES * len(images)):
            for step in range(len(names)):
                name = names[(column + step) % len(names)]
                started = time.perf_counter()
                runs[name].run(images[column % len(images)])
                seconds[name].append(time.perf_counter() - started)
    finally:
        for run in runs.values():
            run.close()
    medians = {name: float(np.median(values)) for name, values in seconds.items()}
    print(json.dumps({"control": str(control), "int8": str(int8), "frames": len(images), "passes": PASSES,
                      "machine": f"{platform.processor() or platform.machine()}, 2 threads",
                      "median_ms": {name: round(1e3 * value, 2) for name, value in medians.items()},
                      "ratio": round(medians["int8, each crop twice"] / medians["fp32, each crop once"], 3)}))


if __name__ == "__main__":
    main()
