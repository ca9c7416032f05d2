"""AP50 of the two scenes' bundles on PETS09's dev frames, by half and seed (frozen; see README.md).

    PYTHONPATH=. python experiments/2026-11-30-walkers-scene-compiled/summarise.py EVAL_DIR [--out FILE.md]

``EVAL_DIR/{tsai,walkers}{seed}/{1,201}/metrics.json``: ``vc-eval`` of each bundle on frames 1-200 and 201-400,
every 5th.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

SCENES = ("tsai", "walkers")
HALVES = {"1": "1-200", "201": "201-400"}
DETECTORS = {"tracked": "visual compiler", "each frame": "visual compiler, each frame on its own"}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("evals", type=Path)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    seeds = sorted({path.name[len(scene):] for scene in SCENES for path in args.evals.glob(f"{scene}[0-9]")})
    lines = ["| frames | AP50 | seed | Tsai scene | walkers' scene | difference |", "|---|---|---|---|---|---|"]
    for half, frames in HALVES.items():
        for label, detector in DETECTORS.items():
            differences = []
            for seed in seeds:
                values = []
                for scene in SCENES:
                    path = args.evals / f"{scene}{seed}" / half / "metrics.json"
                    values.append(json.loads(path.read_text())["detectors"][detector]["ap50"]
                                  if path.is_file() else None)
                if None in values:
                    continue
                differences.append(values[1] - values[0])
                lines.append(f"| {frames} | {label} | {seed} | {values[0]:.3f} | {values[1]:.3f} | "
                             f"{values[1] - values[0]:+.3f} |")
            if differences:
                lines.append(f"| {frames} | {label} | mean | | | **{np.mean(differences):+.3f}** |")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
