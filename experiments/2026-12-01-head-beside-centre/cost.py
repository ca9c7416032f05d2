"""What the head network costs a frame: today's bundle against the union (``union.py``) and the one network with a
head map (``measure_both.py``), numpy decoder for all, on TUD-Stadtmitte's frames 1-90 (frozen experiment).

    PYTHONPATH=../.. python cost.py CONTROL_BUNDLE HEAD_BUNDLE BOTH_BUNDLE

Each arm runs the 90 frames twice in this process, one after another; the second pass is timed (median ms a frame,
``Runtime.run`` end to end, regions in parallel, 2 threads). Ratios are to today's bundle in the same run.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import measure_both
import numpy as np
import union
from union import crowd_measure, second_look, visible_decode

import vc.deploy.runtime as runtime
from vc.deploy.frames import FrameRange, FrameSource

_PEOPLE = runtime.RegionRunner.people


def median_ms(bundle: Path, frames: list[np.ndarray]) -> float:
    with runtime.Runtime(bundle, threads=2) as running:
        seconds = []
        for image in frames + frames:
            start = time.perf_counter()
            running.run(image)
            seconds.append(time.perf_counter() - start)
    return float(np.median(seconds[len(frames):]) * 1000)


def main() -> None:
    control, head, both = (Path(arg) for arg in sys.argv[1:4])
    frames = [frame.image for frame in FrameSource(crowd_measure.TUD["video"], FrameRange.parse("1:90"))]
    visible_decode.install(set(), None, 20.0, 20.0)
    today = median_ms(control, frames)
    second_look.HEAD_MODEL.append(head / "models" / "r0.onnx")
    runtime.RegionRunner.people = union._people
    two = median_ms(control, frames)
    runtime.RegionRunner.people = measure_both.people
    one = median_ms(both, frames)
    runtime.RegionRunner.people = _PEOPLE
    print(f"ms a frame (median), TUD-Stadtmitte 1-90: today {today:.1f}; today's r0 + the head network "
          f"{two:.1f} ({two / today:.2f}x); one network with a head map {one:.1f} ({one / today:.2f}x)")


if __name__ == "__main__":
    main()
