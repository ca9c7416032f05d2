"""The product's decoder (``vc.deploy.decode`` step 5, C where built) on this experiment's every-region bundles,
whose head and size maps lie in two of the fine centre maps (frozen experiment, issue 57 item 2).

    PYTHONPATH=../..:../../src:../2026-12-01-head-beside-centre:../2026-12-01-visible-anchor \
        python product_decode.py CAMERA SEED BUNDLE

Each region's heat maps are given to the runtime with the head map (``train_both.HEAD_CHANNEL``) and the size map
(``train_both.SIZE_CHANNEL``) appended, the layout the product trains (``vc.deploy.heatmaps.HEAD_CHANNELS``); the
runtime then decodes and keeps people as the product does. Measured as ``measure_heads.py`` measures, as arm
``product_all``: against ``head_all`` it says whether the product reads these networks as the experiment did.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import measure_heads
import numpy as np
from train_both import HEAD_CHANNEL, SIZE_CHANNEL

import vc.deploy.runtime as runtime

_HEATMAPS = runtime.RegionRunner.heatmaps


def with_head_layout(self, frame: np.ndarray) -> np.ndarray:
    maps = _HEATMAPS(self, frame)
    return np.concatenate([maps, maps[[HEAD_CHANNEL, SIZE_CHANNEL]]])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera")
    parser.add_argument("seed", type=int)
    parser.add_argument("bundle", type=Path)
    args = parser.parse_args()
    runtime.RegionRunner.heatmaps = with_head_layout
    measure_heads.measure_arm(args.camera, "product_all", args.seed, args.bundle)


if __name__ == "__main__":
    main()
