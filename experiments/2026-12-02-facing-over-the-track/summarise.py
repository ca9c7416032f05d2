"""The table of arms.py's rows: pose agreement tracked with YOLO11n-pose @1280 for each arm, the mean of the seeds and
each seed's change against the control, with the agreement each frame on its own beside it (frozen).

    python experiments/2026-12-02-facing-over-the-track/summarise.py results/arms.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

HALVES = {1: "choosing", 91: "confirming", 201: "confirming"}
ARMS = ("tall: the model", "tall: the track's vote", "tall: a 3 s vote", "tall: the model, unless the walk is clear",
        "tall: the vote, unless the walk is clear", "tall: a 3 s vote, unless the walk is clear",
        "everyone: the vote where the walk is unclear")


def main() -> None:
    table: dict[tuple, dict[str, dict[int, float]]] = defaultdict(lambda: defaultdict(dict))
    swapped: dict[tuple, dict[str, list[int]]] = defaultdict(lambda: defaultdict(list))
    for line in open(sys.argv[1]):
        row = json.loads(line)
        key = (row["camera"], HALVES[row["frames"][0]])
        for arm in ("each frame", "control", *ARMS):
            table[key][arm][row["seed"]] = row[arm]["overall"]
            swapped[key][arm].append(row[arm]["swapped"])
    print("| camera | half | arm | seeds | tracked agreement: control → arm | change per seed | people swapped |")
    print("|---|---|---|---|---|---|---|")
    for (camera, half), arms in sorted(table.items()):
        seeds = sorted(arms["control"])
        control = np.array([arms["control"][seed] for seed in seeds])
        each = np.array([arms["each frame"][seed] for seed in seeds])
        print(f"| {camera} | {half} | each frame on its own | {', '.join(map(str, seeds))} | {each.mean():.3f} | "
              f"| {sum(swapped[(camera, half)]['each frame'])} |")
        print(f"| {camera} | {half} | control (tracked, as shipped) | {', '.join(map(str, seeds))} | "
              f"{control.mean():.3f} | | {sum(swapped[(camera, half)]['control'])} |")
        for arm in ARMS:
            values = np.array([arms[arm][seed] for seed in seeds])
            changes = " / ".join(f"{change:+.3f}" for change in values - control)
            print(f"| {camera} | {half} | {arm} | {', '.join(map(str, seeds))} | "
                  f"{control.mean():.3f} → **{values.mean():.3f}** | {changes} | "
                  f"{sum(swapped[(camera, half)][arm])} |")


if __name__ == "__main__":
    main()
