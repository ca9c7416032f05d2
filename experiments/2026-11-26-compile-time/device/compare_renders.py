"""Two renders of the same dataset samples (e.g. the GPU's from render_check_gpu.sh against this machine's
``vc-render SCENE -o DIR --samples N``), image by image: how many pixels differ, and by how much.

    python experiments/2026-11-26-compile-time/device/compare_renders.py GPU_DATASET CPU_DATASET

Each sample's people, light, noise and ray seeds follow from its index, so two backends agree up to float
rounding; prints, per region, the mean absolute difference (8-bit levels) and the share of pixels more than 2
levels apart, and exits 1 where that share exceeds 0.2 %.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from vc.io import read_image

#: Above this share of pixels more than 2 levels apart, the backends do not render the same thing (the OptiX
#: fault of 2026-11-26 gave 1.4-1.6 %).
MAX_SHARE_OFF = 0.002


def compare(first: Path, second: Path) -> dict[str, dict]:
    result = {}
    for region in sorted(p.name for p in first.iterdir() if p.is_dir()):
        images = sorted((first / region).glob("shard-*/images/*.png"))
        differences = []
        for image in images:
            other = second / image.relative_to(first)
            if not other.is_file():
                raise FileNotFoundError(f"{other}: not in the second dataset (render the same samples of the same "
                                        f"scene file there)")
            a = read_image(image).astype(np.int16)
            b = read_image(other).astype(np.int16)
            differences.append(np.abs(a - b).max(axis=-1))
        stacked = np.stack(differences) if differences else np.zeros((0, 1, 1))
        result[region] = {"images": len(images), "mean_abs_levels": round(float(stacked.mean()), 4),
                          "share_over_2_levels": round(float((stacked > 2).mean()), 5)}
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("first", type=Path)
    parser.add_argument("second", type=Path)
    args = parser.parse_args()
    for folder in (args.first, args.second):
        if not folder.is_dir():
            parser.error(f"{folder}: not a folder")
    try:
        result = compare(args.first, args.second)
    except FileNotFoundError as error:
        parser.error(str(error))
    for region, row in result.items():
        print(f"{region}: {row['images']} images, mean |difference| {row['mean_abs_levels']} levels, "
              f"{100 * row['share_over_2_levels']:.3f} % of pixels over 2 levels")
    sys.exit(1 if any(row["share_over_2_levels"] > MAX_SHARE_OFF for row in result.values()) else 0)


if __name__ == "__main__":
    main()
