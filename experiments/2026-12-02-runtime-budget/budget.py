"""What issue 57's per-person models cost a frame, and what the C decoder gave back since the issue was filed (frozen).

    PYTHONPATH=src:. python experiments/2026-12-02-runtime-budget/budget.py BUNDLE BARE VIDEO FRAMES PASSES \
        >> results/budget.jsonl

BUNDLE is a compile's bundle as shipped; BARE the same bundle with the facing and keypoint models taken out of its
manifest (``strip_person_models``), so that the runtime reads neither: what the runtime was per frame before issue
57 added them, on today's networks. Each arm is a Runtime of its own, regions in parallel on 2 threads, and every
frame is run by each arm in turn, the order rotated from frame to frame (as benchmarks.runtime_interleaved times
bundles, so that a shared machine's drift slows every arm alike). Arms: the bare bundle decoded by numpy (the
decoder when issue 57 was filed), the bare bundle decoded in C, the bundle as shipped decoded in C (the default).
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np

from benchmarks.runtime_interleaved import timed_in_turn
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

PERSON_MODELS = ("facing", "crop_pose")


def strip_person_models(bundle: Path, bare: Path) -> None:
    """A copy of ``bundle`` at ``bare`` whose manifest names neither person model."""
    shutil.rmtree(bare, ignore_errors=True)
    shutil.copytree(bundle, bare)
    manifest = json.loads((bare / "manifest.json").read_text())
    for key in PERSON_MODELS:
        manifest.pop(key, None)
    (bare / "manifest.json").write_text(json.dumps(manifest, indent=1))


def main() -> None:
    bundle, bare, video = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    frames_range, passes = FrameRange.parse(sys.argv[4]), int(sys.argv[5])
    strip_person_models(bundle, bare)
    arms = {"without the person models, numpy decoder": (bare, "numpy"),
            "without the person models, C decoder": (bare, "c"),
            "as shipped (C decoder)": (bundle, "c")}
    frames = [frame.image for frame in FrameSource(video, frames_range)]
    runtimes = [Runtime(path, threads=2, parallel_regions=True, decoder=decoder) for path, decoder in arms.values()]
    seconds = timed_in_turn(runtimes, frames, passes)
    for runtime in runtimes:
        runtime.close()
    reference, rows = seconds[0], dict(zip(arms, seconds, strict=True))
    print(json.dumps({"bundle": str(bundle), "video": str(video), "frames": sys.argv[4], "passes": passes,
                      "machine": next(line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                                      if line.startswith("model name")),
                      "median_ms": {name: round(float(np.median(row)) * 1e3, 2) for name, row in rows.items()},
                      "median_of_frame_ratios_to_numpy_bare": {
                          name: round(float(np.median(row / reference)), 3) for name, row in rows.items()}}))


if __name__ == "__main__":
    main()
