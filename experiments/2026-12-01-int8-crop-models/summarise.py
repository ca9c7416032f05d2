"""The int8 crop models' tables: held-out renders, fp32 against int8 (quantize.py's rows), and pose agreement and
time a frame on real frames (arms.py's rows), the mean of the seeds and each seed's change (frozen).

    python experiments/2026-12-01-int8-crop-models/summarise.py results/quantize.jsonl results/arms.jsonl \
        > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

HALVES = {1: "choosing", 91: "confirming", 201: "confirming"}
ARMS = ("int8", "int8, keypoints read twice")


def main() -> None:
    quantized = [json.loads(line) for line in open(sys.argv[1])]
    print("| bundle | facing accuracy / AUC, fp32 → int8 | ms a crop | keypoint model PCKh, fp32 → int8 | ms a crop |")
    print("|---|---|---|---|---|")
    for row in quantized:
        facing = f"{row['facing fp32']['accuracy']:.4f} / {row['facing fp32']['auc']:.4f} → " \
                 f"{row['facing int8']['accuracy']:.4f} / {row['facing int8']['auc']:.4f}"
        facing_ms = f"{row['facing fp32']['ms_a_crop']:.2f} → {row['facing int8']['ms_a_crop']:.2f}"
        pose, pose_ms = "–", "–"
        if "keypoint model fp32" in row:
            pose = f"{row['keypoint model fp32']['pckh']:.4f} → {row['keypoint model int8']['pckh']:.4f}"
            pose_ms = f"{row['keypoint model fp32']['ms_a_crop']:.2f} → {row['keypoint model int8']['ms_a_crop']:.2f}"
        print(f"| {row['bundle']} | {facing} | {facing_ms} | {pose} | {pose_ms} |")
    print()
    table: dict[tuple, dict[str, dict[int, float]]] = defaultdict(lambda: defaultdict(dict))
    times: dict[tuple, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for line in open(sys.argv[2]):
        row = json.loads(line)
        half = HALVES[row["frames"][0]]
        for arm in ARMS:
            times[(row["camera"], half)][arm].append(row["time_ratio"][arm])
        for reading in ("each frame", "tracked"):
            for arm in ("control", *ARMS):
                table[(row["camera"], half, reading)][arm][row["seed"]] = row[f"{arm}, {reading}"]["overall"]
    print("| camera | half | reading | arm | seeds | agreement: control → arm | change per seed |")
    print("|---|---|---|---|---|---|---|")
    for (camera, half, reading), arms in sorted(table.items()):
        seeds = sorted(arms["control"])
        control = np.array([arms["control"][seed] for seed in seeds])
        for arm in ARMS:
            values = np.array([arms[arm][seed] for seed in seeds])
            changes = " / ".join(f"{change:+.3f}" for change in values - control)
            print(f"| {camera} | {half} | {reading} | {arm} | {', '.join(map(str, seeds))} | "
                  f"{control.mean():.3f} → **{values.mean():.3f}** | {changes} |")
    print()
    print("Time a frame against the control's, frame by frame in one process (each seed):")
    print()
    for (camera, half), arms in sorted(times.items()):
        for arm, ratios in arms.items():
            print(f"- {camera}, {half}, {arm}: {', '.join(f'{ratio:.2f}x' for ratio in ratios)}")


if __name__ == "__main__":
    main()
