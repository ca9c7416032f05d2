"""results/ceiling.jsonl as the README's tables: overall agreement per reading (mean over the seeds measured), and
the keypoints that stay low with both readings taken from the reference.

    python experiments/2026-12-01-pose-ceiling/summarise.py results/ceiling.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

READINGS = ("as shipped", "face turned by the reference", "pairs in the reference's order", "both")


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1])]
    groups: dict[tuple, list[dict]] = defaultdict(list)
    for row in rows:
        half = "choosing" if row["frames"][0] == 1 else "confirming"
        groups[(row["camera"], half, "tracked" if row["tracked_fps"] else "each frame")].append(row)
    print("| camera | half | reading | seeds | people | " + " | ".join(READINGS) + " |")
    print("|---|---|---|---|---|" + "---|" * len(READINGS))
    for (camera, half, mode), group in sorted(groups.items()):
        cells = [f"{np.mean([row[name]['overall'] for row in group]):.3f}" for name in READINGS]
        people = "/".join(str(row["as shipped"]["people"]) for row in group)
        print(f"| {camera} | {half} | {mode} | {len(group)} | {people} | " + " | ".join(cells) + " |")
    print()
    print("Per keypoint with both readings from the reference (confirming halves, tracked, mean over seeds):")
    print()
    for camera in ("pets", "tud"):
        group = groups.get((camera, "confirming", "tracked"), [])
        if not group:
            continue
        names = list(group[0]["both"]["per_keypoint"])
        means = {name: np.mean([row["both"]["per_keypoint"][name] for row in group]) for name in names}
        print(f"- {camera}: " + ", ".join(f"{name} {value:.2f}" for name, value in means.items()))


if __name__ == "__main__":
    main()
