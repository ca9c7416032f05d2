"""Each arm's pose agreement tracked, mean over the seeds measured, per camera and half, with each seed's change
from the tracker as shipped and the people read with left and right exchanged (frozen).

    python experiments/2026-12-02-small-people-voted/summarise.py results/arms.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys

import numpy as np

HALVES = ("choosing", "confirming")


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
    arms = [key for key, value in rows[0].items() if isinstance(value, dict)]
    for camera in dict.fromkeys(row["camera"] for row in rows):
        mine = [row for row in rows if row["camera"] == camera]
        seeds = sorted({row["seed"] for row in mine})
        print(f"## {camera}, seeds {', '.join(map(str, seeds))}\n")
        print("| arm | choosing (mean) | confirming (mean) | choosing, each seed's change | confirming, each seed's "
              "change | people exchanged, choosing / confirming |")
        print("|---|---|---|---|---|---|")
        for arm in arms:
            cells, changes, exchanged = [], [], []
            for half in HALVES:
                by_seed = {row["seed"]: row for row in mine if row["half"] == half}
                cells.append(f"{np.mean([by_seed[s][arm]['overall'] for s in seeds]):.3f}")
                changes.append(" / ".join(f"{by_seed[s][arm]['overall'] - by_seed[s]['as shipped']['overall']:+.3f}"
                                          for s in seeds))
                exchanged.append(str(sum(by_seed[s][arm]["swapped"] for s in seeds)))
            print(f"| {arm} | {cells[0]} | {cells[1]} | {changes[0]} | {changes[1]} | {' / '.join(exchanged)} |")
        print()


if __name__ == "__main__":
    main()
