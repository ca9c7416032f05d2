"""The behind-as-weak probe's figures, arm by arm, seed by seed and as means over the seeds every arm has
(frozen experiment).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
ARMS = ("today", "maps_not_read", "weak_0.3", "weak_0.5")
HALVES = ("choosing", "confirming")
COLUMNS = {
    "AP50 tracked": lambda r: r["ap50_tracked"],
    "each frame": lambda r: r["ap50_each_frame"],
    "recall / precision at the operating point": lambda r: (r["recall"], r["precision"]),
    "overlapping another, at the operating point": lambda r: r["recall_by_group"]["overlapping another"]["recall"],
    "duplicates + merged": lambda r: r["false_positives"]["duplicate"] + r["false_positives"]["merged"],
    "everyone reported: recall / precision": lambda r: (r["everyone_reported"]["recall"],
                                                        r["everyone_reported"]["precision"]),
    "everyone reported: overlapping another": lambda r: r["everyone_reported"]["recall_overlapping"],
    "MOTA / IDF1": lambda r: (r["tracking"]["mota"], r["tracking"]["idf1"]),
}


def _cell(value) -> str:
    return " / ".join(f"{v:.3f}" for v in value) if isinstance(value, tuple) else (
        f"{value:.3f}" if isinstance(value, float) else str(value))


def _mean(values: list) -> object:
    if isinstance(values[0], tuple):
        return tuple(float(np.mean(column)) for column in zip(*values, strict=True))
    return float(np.mean(values)) if isinstance(values[0], float) else f"{np.mean(values):.1f}"


def main() -> None:
    rows = {}
    for path in sorted(RESULTS.glob("*/seed*_*.json")):
        seed, half = path.stem.removeprefix("seed").split("_")
        rows[(path.parent.name, int(seed), half)] = json.loads(path.read_text())
    seeds = sorted({seed for _, seed, _ in rows})
    print("| arm | seed | half | " + " | ".join(COLUMNS) + " |")
    print("|---|---|---|" + "---|" * len(COLUMNS))
    for half in HALVES:
        for seed in seeds:
            for arm in ARMS:
                if (arm, seed, half) in rows:
                    row = rows[(arm, seed, half)]
                    print(f"| {arm} | {seed} | {half} | " + " | ".join(_cell(f(row)) for f in COLUMNS.values()) + " |")
    common = [seed for seed in seeds if all((arm, seed, half) in rows for arm in ARMS[:3] for half in HALVES)]
    print(f"\nMeans over seeds {', '.join(map(str, common))}:\n")
    print("| arm | half | " + " | ".join(COLUMNS) + " |")
    print("|---|---|" + "---|" * len(COLUMNS))
    for half in HALVES:
        for arm in ARMS[:3]:
            cells = [_cell(_mean([f(rows[(arm, seed, half)]) for seed in common])) for f in COLUMNS.values()]
            print(f"| {arm} | {half} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
