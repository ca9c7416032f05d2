"""Pose agreement of each arm of ``results/tud.jsonl``, seed by seed and their mean: ``python summarise.py``."""

from __future__ import annotations

import json
from pathlib import Path

HALVES = {1: "choosing", 91: "confirming"}


def main() -> None:
    rows = [json.loads(line) for line in (Path(__file__).parent / "results" / "tud.jsonl").open()]
    arms = list(rows[0]["time_ratio"])
    print("| half | reading | arm | seeds 0 / 1 / 2 | mean | people swapped (mean) | time a frame |")
    print("|---|---|---|---|---|---|---|")
    for first, half in HALVES.items():
        chosen = sorted((row for row in rows if row["frames"][0] == first), key=lambda row: row["seed"])
        for mode in ("each frame", "tracked"):
            for arm in arms:
                values = [row["readings"][f"{arm}, {mode}"] for row in chosen]
                ratio = sum(row["time_ratio"][arm] for row in chosen) / len(chosen)
                each = " / ".join(f"{value['overall']:.3f}" for value in values)
                print(f"| {half} | {mode} | {arm} | {each} "
                      f"| {sum(v['overall'] for v in values) / len(values):.3f} "
                      f"| {sum(v['swapped'] for v in values) / len(values):.0f} | {ratio:.2f}x |")


if __name__ == "__main__":
    main()
