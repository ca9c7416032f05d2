"""The narrow head network's union beside 0036's arms: AP50 tracked and each frame, recall of people overlapping
another and apart, on TUD-Stadtmitte's halves, seed by seed and their mean (frozen experiment, issue 57 item 2).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent / "2026-12-01-head-beside-centre"))
from summarise import HALVES, cell  # noqa: E402  (0036's table cells: seeds and their mean)

EXPERIMENTS = HERE.parent
ARMS = {
    "today's bundle (control)": EXPERIMENTS / "2026-12-01-tud-denser-crowd" / "results" / "crowd_5",
    "today's r0 + the head network (width 32, 0036), one head one person (0.1)":
        EXPERIMENTS / "2026-12-01-head-beside-centre" / "results" / "union_samehead0.1",
    "today's r0 + a head network of width 16, one head one person (0.1)": HERE / "results" / "small_samehead0.1",
}
FIGURES = {"AP50 tracked": lambda d: d["ap50_tracked"], "AP50 each frame": lambda d: d["ap50_each_frame"],
           "recall, overlapping another": lambda d: d["recall_by_group"]["overlapping another"]["recall"],
           "recall, apart": lambda d: d["recall_by_group"]["apart"]["recall"]}


def main() -> None:
    for half in HALVES:
        print(f"\n{half} half, seeds 0 / 1 / 2 (mean)\n")
        print("| arm | " + " | ".join(FIGURES) + " |\n|---|" + "---|" * len(FIGURES))
        for arm, folder in ARMS.items():
            print(f"| {arm} | " + " | ".join(cell(folder, half, key) for key in FIGURES.values()) + " |")


if __name__ == "__main__":
    main()
