"""The arms' table: pose agreement per camera, half and reading, each arm against the control, the mean of the seeds
and each seed's change; people read with left and right exchanged; then what a frame costs, from latency.py's rows
(the arms' own times are not used: they read every crop twice and kept the mirror's reading only where an arm says;
frozen).

    python experiments/2026-12-01-mirrored-crops/summarise.py results/*.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

HALVES = {1: "choosing", 91: "confirming", 201: "confirming"}


def main() -> None:
    rows = [json.loads(line) for path in sys.argv[1:] for line in open(path)]
    latency = [row for row in rows if "passes" in row]
    table: dict[tuple, dict[str, dict[int, tuple]]] = defaultdict(lambda: defaultdict(dict))
    for row in rows:
        if "passes" in row:
            continue
        half = HALVES[row["frames"][0]]
        for key, entry in row.items():
            if not isinstance(entry, dict) or "overall" not in entry:
                continue
            arm, reading = key.rsplit(", ", 1)
            table[(row["camera"], half, reading)][arm][row["seed"]] = (entry["overall"], entry["swapped"])
    print("| camera | half | reading | arm | seeds | agreement: control → arm | change per seed | people swapped |")
    print("|---|---|---|---|---|---|---|---|")
    for (camera, half, reading), arms in sorted(table.items()):
        control = arms["control"]
        for arm, seeds in arms.items():
            if arm == "control":
                continue
            order = sorted(seeds)
            before = np.array([control[seed][0] for seed in order])
            after = np.array([seeds[seed][0] for seed in order])
            changes = " / ".join(f"{change:+.3f}" for change in after - before)
            swapped = f"{sum(control[s][1] for s in order)} → {sum(seeds[s][1] for s in order)}"
            print(f"| {camera} | {half} | {reading} | {arm} | {', '.join(map(str, order))} | "
                  f"{before.mean():.3f} → **{after.mean():.3f}** | {changes} | {swapped} |")
    print()
    print("| camera | bundle | frames x passes | read once (ms) | facing read twice | keypoints read twice | both |")
    print("|---|---|---|---|---|---|---|")
    for row in latency:
        ratio = row["ratio"]
        print(f"| {row['camera']} | {row['bundle']} | {row['frames']} x {row['passes']} | "
              f"{row['median_ms']['read once']:.1f} | {ratio['facing read twice']:.2f}x | "
              f"{ratio['keypoints read twice']:.2f}x | {ratio['tall people read twice']:.2f}x |")


if __name__ == "__main__":
    main()
