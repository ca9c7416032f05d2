"""The tracker arms against the control, seeds' means per camera and half (frozen, issue 57).

    python experiments/2026-11-30-a-walk-that-is-not-a-walk/summarise.py CONTROL_DIR ARM_DIR... \
        > results/tracker_arms.md

Each directory holds vc-eval outputs as DIR/{pets,tud}{0,1,2}/{1,201,91}/metrics.json; an arm is named by its
directory (``size_gate_G``, ``walk_growth_W``, or both).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HALVES = (("pets", "1", "choosing"), ("pets", "201", "confirming"), ("tud", "1", "choosing"),
          ("tud", "91", "confirming"))


def figures(metrics: dict) -> dict:
    ours = "visual compiler"
    accuracy = metrics["tracking"]["accuracy"]
    pose = metrics["pose_agreement"]["agreement"][ours]
    return {"AP50 tracked": metrics["detectors"][ours]["ap50"], "MOTA": accuracy["mota"], "IDF1": accuracy["idf1"],
            "identity switches": accuracy["id_switches"], "pose tracked": pose["overall"]}


def main() -> None:
    arms = [Path(path) for path in sys.argv[1:]]
    print("| camera, half | arm | " + " | ".join(figures_names := ["AP50 tracked", "MOTA", "IDF1",
                                                                      "identity switches", "pose tracked"])
          + " | per seed AP50 tracked | per seed pose tracked |")
    print("|---|---|" + "---|" * (len(figures_names) + 2))
    for camera, half, label in HALVES:
        for arm in arms:
            runs = [arm / f"{camera}{seed}" / half / "metrics.json" for seed in (0, 1, 2)]
            if not all(run.is_file() for run in runs):
                continue
            rows = [figures(json.loads(run.read_text())) for run in runs]
            means = {name: np.mean([row[name] for row in rows]) for name in figures_names}
            print(f"| {camera} {half} ({label}) | {arm.name} | "
                  + " | ".join(f"{means[name]:.1f}" if name == "identity switches" else f"{means[name]:.4f}"
                               for name in figures_names)
                  + " | " + " / ".join(f"{row['AP50 tracked']:.4f}" for row in rows)
                  + " | " + " / ".join(f"{row['pose tracked']:.4f}" for row in rows) + " |")


if __name__ == "__main__":
    main()
