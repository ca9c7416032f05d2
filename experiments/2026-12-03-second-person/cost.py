"""What a TUD-Stadtmitte frame costs with the people behind added, and where it goes (frozen experiment, issue 57
item 2).

    PYTHONPATH=src:experiments/2026-12-03-second-person python experiments/2026-12-03-second-person/cost.py \
        TODAY BEHIND [FRAMES]

Reads frames 1..FRAMES (default 60) with today's bundle and the behind bundle in four ways, in turn frame by frame
(the order rotated), each with the numpy decoder: today's; the behind bundle with its three maps not read; people
behind added at T = 0.3 in one decode (they compete for keypoints and mask cells); and added with the people in front
kept (two decodes, as ``real.py`` and ``pose.py`` measure). Prints each arm's median ms a frame, its ratio to today's,
and the people reported a frame.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import real
import second_person

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

VIDEO = Path("../shared/data/tud_stadtmitte/frames")
#: name: (bundle index, threshold, front kept)
ARMS = {"today": (0, None, False), "behind, maps not read": (1, None, False),
        "behind, T 0.3, one decode": (1, 0.3, False), "behind, T 0.3, front kept": (1, 0.3, True)}


def main() -> None:
    bundles = [Path(sys.argv[1]), Path(sys.argv[2])]
    frames = int(sys.argv[3]) if len(sys.argv) > 3 else 60
    real.install()
    runtimes = [Runtime(bundle, threads=2) for bundle in bundles]
    names = list(ARMS)
    seconds: dict[str, list[float]] = {name: [] for name in names}
    people: dict[str, list[int]] = {name: [] for name in names}
    try:
        for count, frame in enumerate(FrameSource(VIDEO, FrameRange(1, frames, 1))):
            for turn in range(len(names)):
                name = names[(count + turn) % len(names)]
                index, threshold, front_kept = ARMS[name]
                second_person.THRESHOLD[0], second_person.FRONT_KEPT[0] = threshold, front_kept
                start = time.perf_counter()
                result = runtimes[index].run(frame.image)
                seconds[name].append(time.perf_counter() - start)
                people[name].append(len(result.people))
    finally:
        for runtime in runtimes:
            runtime.close()
    today = float(np.median(seconds["today"]))
    for name in names:
        median = float(np.median(seconds[name]))
        print(f"{name}: {1000 * median:.1f} ms a frame ({median / today:.2f}x), {np.mean(people[name]):.1f} people "
              f"a frame")


if __name__ == "__main__":
    main()
