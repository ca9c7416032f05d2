"""results/arms.jsonl -> the tables of the README: the classifier's weight on PETS09's choosing half, and control
against the head's colours at the chosen weight, each camera, half and reading (frozen).

    python experiments/2026-12-01-head-colours/summarise.py experiments/2026-12-01-head-colours/results/arms.jsonl \
        > experiments/2026-12-01-head-colours/results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

CHOSEN = 0.05


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1])]
    choosing = {(row["seed"], row["classifier_weight_below"]): row for row in rows
                if row["camera"] == "pets" and row["frames"][0] == 1}
    weights = sorted({weight for _, weight in choosing})
    seeds = sorted(seed for seed in {seed for seed, _ in choosing}
                   if all((seed, weight) in choosing for weight in weights))  # the seeds read at every weight
    print(f"PETS09 choosing half, each frame, the classifier's weight beside the head's (seeds {seeds}, mean):\n")
    print("| weight | agreement |\n|---|---|")
    control = [choosing[(seed, CHOSEN)]["control, each frame"]["overall"] for seed in seeds]
    print(f"| control | {sum(control) / len(control):.4f} |")
    for weight in weights:
        values = [choosing[(seed, weight)]["head colours, each frame"]["overall"] for seed in seeds]
        print(f"| {weight} | {sum(values) / len(values):.4f} |")
    print("\nAt the chosen weight, control -> head's colours (mean of the seeds; change per seed; people read with "
          "left and right exchanged, summed):\n")
    print("| camera | half | reading | seeds | control | head's colours | change per seed | exchanged |")
    print("|---|---|---|---|---|---|---|---|")
    table: dict[tuple, list[dict]] = defaultdict(list)
    for row in rows:
        if row["classifier_weight_below"] == CHOSEN:
            half = "choosing" if row["frames"][0] == 1 else "confirming"
            for reading in ("each frame", "tracked"):
                table[(row["camera"], half, reading)].append(
                    {"seed": row["seed"], "control": row[f"control, {reading}"],
                     "arm": row[f"head colours, {reading}"]})
    for (camera, half, reading), found in sorted(table.items()):
        found.sort(key=lambda entry: entry["seed"])
        before = sum(entry["control"]["overall"] for entry in found) / len(found)
        after = sum(entry["arm"]["overall"] for entry in found) / len(found)
        changes = " / ".join(f"{entry['arm']['overall'] - entry['control']['overall']:+.3f}" for entry in found)
        exchanged = (f"{sum(entry['control']['swapped'] for entry in found)} -> "
                     f"{sum(entry['arm']['swapped'] for entry in found)}")
        print(f"| {'PETS09' if camera == 'pets' else 'TUD-Stadtmitte'} | {half} | {reading} | "
              f"{','.join(str(entry['seed']) for entry in found)} | {before:.3f} | {after:.3f} | {changes} | "
              f"{exchanged} |")


if __name__ == "__main__":
    main()
