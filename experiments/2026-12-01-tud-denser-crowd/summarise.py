"""The denser-crowd arm's table: per arm and half, AP50 tracked and each frame, recall of people overlapping another,
of people 100 px and taller, precision at the operating point, MOTA and IDF1, seeds 0 / 1 / 2 with their mean
(frozen).

    python summarise.py results > results/summary.md
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

ARMS = ("crowd_10", "crowd_5")
HALVES = ("choosing", "confirming")


def _row(values: list[float]) -> str:
    return f"{' / '.join(f'{value:.3f}' for value in values)} ({sum(values) / len(values):.3f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path)
    root = parser.parse_args().results
    print("| arm | half | AP50 tracked | each frame | overlapping another | >= 100 px | precision | MOTA | IDF1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for arm in ARMS:
        for half in HALVES:
            runs = [json.loads(path.read_text()) for path in sorted((root / arm).glob(f"seed*_{half}.json"))]
            if not runs:
                continue
            columns = [[run["ap50_tracked"] for run in runs], [run["ap50_each_frame"] for run in runs],
                       [run["recall_by_group"]["overlapping another"]["recall"] for run in runs],
                       [run["recall_by_height"][">= 100 px"]["recall"] for run in runs],
                       [run["precision"] for run in runs], [run["tracking"]["mota"] for run in runs],
                       [run["tracking"]["idf1"] for run in runs]]
            print(f"| {arm} | {half} | " + " | ".join(_row(column) for column in columns) + " |")


if __name__ == "__main__":
    main()
