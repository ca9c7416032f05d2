"""The cut-box arm's table: AP50 tracked and each frame, and recall of the people the frame cuts, per variant, seed
and half, with the seeds' means (frozen experiment).

    python summarise.py results/tud > results/summary_tud.md
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

HALVES = ("choosing", "confirming")
VARIANTS = ("before", "feet", "edge_box", "both")  # cut_box.py's


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path)
    root = parser.parse_args().results
    print("| variant | half | AP50 tracked, seeds 0 / 1 / 2 (mean) | each frame (mean) | cut by the frame: found "
          "of (tracked) |")
    print("|---|---|---|---|---|")
    for variant in VARIANTS:
        for half in HALVES:
            runs = [json.loads(path.read_text()) for path in sorted((root / variant).glob(f"seed*_{half}.json"))]
            if not runs:
                continue
            tracked = [run["ap50_tracked"] for run in runs]
            each = [run["ap50_each_frame"] for run in runs]
            cut = [run["recall_by_edge"].get("cut by the frame", {}) for run in runs]
            found = " / ".join(f"{round(c['recall'] * c['people'])} of {c['people']}" for c in cut if c)
            print(f"| {variant} | {half} | {' / '.join(f'{v:.4f}' for v in tracked)} ({sum(tracked) / len(runs):.4f}) "
                  f"| {' / '.join(f'{v:.4f}' for v in each)} ({sum(each) / len(runs):.4f}) | {found} |")


if __name__ == "__main__":
    main()
