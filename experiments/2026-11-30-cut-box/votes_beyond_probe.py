"""Probe (not kept): do the networks' centre offsets put people beyond the map's edge, where a person the frame cuts
has their centre? With ``votes_beyond_the_edge.patch`` applied at aa96de5 (step 1b's votes may lie up to 0.2
heights beyond the map, scored by the centre map's Gaussian continued there), counts over a bundle's regions the
foreground cells voting beyond the map, those within reach, and the people the votes add beyond it (frozen).

    git apply votes_beyond_the_edge.patch && PYTHONPATH=../.. python votes_beyond_probe.py BUNDLE FRAMES

TUD-Stadtmitte, seed 0's bundle, frames 1:90:3: 36 votes beyond the map, 29 within reach, no one added (955 people
added on the maps by the votes): the offsets do not reach beyond the edge, so the patch changes nothing.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import vc.deploy.decode as decode
import vc.deploy.native as native
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

TUD_FRAMES = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "tud_stadtmitte" / "frames"


def main() -> None:
    bundle, frames = Path(sys.argv[1]), FrameRange.parse(sys.argv[2])
    native.default_decoder = lambda: "numpy"  # the patch is the numpy decoder's
    counts = {"votes_beyond": 0, "within_reach": 0, "added": 0, "added_beyond": 0}
    original = decode._vote_centres

    def counted(voted, weights, vote_heights, shape, peaks, peak_heights, config):
        height, width = shape
        rounded = np.round(voted)
        over = np.hypot(*np.maximum(np.maximum(-rounded, rounded - [width - 1, height - 1]), 0.0).T)
        counts["votes_beyond"] += int((over > 0).sum())
        counts["within_reach"] += int(((over > 0) & (over <= decode.BEYOND_EDGE_REACH * vote_heights)).sum())
        moved, added = original(voted, weights, vote_heights, shape, peaks, peak_heights, config)
        counts["added"] += len(added)
        counts["added_beyond"] += sum(not (-0.5 <= x < width - 0.5 and -0.5 <= y < height - 0.5) for x, y in added)
        return moved, added

    decode._vote_centres = counted
    with Runtime(bundle, threads=1) as runtime:
        for frame in FrameSource(TUD_FRAMES, frames):
            runtime.run(frame.image)
    print(counts)


if __name__ == "__main__":
    main()
