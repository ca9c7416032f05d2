"""results/summary.md from results/arms.jsonl: pose agreement per arm, seed by seed and their mean, each half
(frozen experiment).

    python experiments/2026-12-02-keypoint-model-capacity/summarise.py RESULTS/arms.jsonl > RESULTS/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

HALVES = {1: "choosing (1–90)", 91: "confirming (91–179)"}


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1])]
    table: dict[tuple[str, int], dict[int, float]] = defaultdict(dict)
    ratios: dict[tuple[str, int], dict[int, float]] = defaultdict(dict)
    for row in rows:
        for name, reading in row["readings"].items():
            table[name, row["frames"][0]][row["seed"]] = reading["overall"]
        for name, ratio in row["time_ratio"].items():
            ratios[name, row["frames"][0]][row["seed"]] = ratio
    print("# Pose agreement with YOLO11n-pose @1280, TUD-Stadtmitte, seed by seed (mean of the seeds measured)\n")
    print("| arm | " + " | ".join(HALVES.values()) + " |")
    print("|---|" + "---|" * len(HALVES))
    for name in sorted({name for name, _ in table}, key=lambda n: (n.split(",")[1], n != "control, each frame"
                                                                   and not n.startswith("control"), n)):
        cells = []
        for first in HALVES:
            seeds = table.get((name, first), {})
            values = " / ".join(f"{seeds[s]:.3f}" for s in sorted(seeds))
            cells.append(f"{values} (**{sum(seeds.values()) / len(seeds):.3f}**)" if seeds else "")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("\nTime a frame against the control (median, same process, frames in turn):\n")
    for (name, first), seeds in sorted(ratios.items()):
        print(f"- {name}, {HALVES[first]}: " + ", ".join(f"seed {s} {v:.3f}x" for s, v in sorted(seeds.items())))


if __name__ == "__main__":
    main()
