"""Mean pose agreement of each arm over the seeds, per camera and half, each frame and tracked, and each seed's
change from the bundle as shipped (frozen).

    python experiments/2026-12-02-pairs-in-profile/summarise.py results/arms.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
    by = defaultdict(dict)  # (camera, arm, half, reading) -> seed -> (overall, swapped)
    for row in rows:
        for reading in ("each frame", "tracked"):
            by[row["camera"], row["arm"], row["half"], reading][row["seed"]] = (row[reading]["overall"],
                                                                                 row[reading]["swapped"])
    arms = list(dict.fromkeys(row["arm"] for row in rows))
    for camera in dict.fromkeys(row["camera"] for row in rows):
        print(f"## {camera}\n")
        print("| arm | reading | choosing (mean) | confirming (mean) | choosing, each seed's change | "
              "confirming, each seed's change | people exchanged, choosing / confirming |")
        print("|---|---|---|---|---|---|---|")
        for arm in arms:
            for reading in ("each frame", "tracked"):
                cells, changes, exchanged = [], [], []
                for half in ("choosing", "confirming"):
                    seeds = by.get((camera, arm, half, reading), {})
                    shipped = by.get((camera, "as shipped", half, reading), {})
                    if not seeds:
                        break
                    cells.append(f"{np.mean([value for value, _ in seeds.values()]):.3f}")
                    changes.append(" / ".join(f"{seeds[seed][0] - shipped[seed][0]:+.3f}" for seed in sorted(seeds)
                                              if seed in shipped))
                    exchanged.append(str(sum(swapped for _, swapped in seeds.values())))
                if len(cells) == 2:
                    print(f"| {arm} | {reading} | {cells[0]} | {cells[1]} | {changes[0]} | {changes[1]} | "
                          f"{' / '.join(exchanged)} |")
        print()


if __name__ == "__main__":
    main()
