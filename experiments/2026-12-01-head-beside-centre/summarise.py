"""The arms' AP50 tracked (and each frame, recall of people overlapping another) on TUD-Stadtmitte's halves, seed by
seed and their mean, as a markdown table (frozen experiment, issue 57 item 2).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).parent
ARMS = {
    "today's bundle (control)": HERE.parent / "2026-12-01-tud-denser-crowd" / "results" / "crowd_5",
    "head network alone, one head one person (0035's best)":
        HERE.parent / "2026-12-01-visible-anchor" / "results" / "head_size_samehead0.1_agree0.15",
    "head network alone": HERE.parent / "2026-12-01-visible-anchor" / "results" / "head_size",
    "today's r0 + the head network's people it lacks (IoU < 0.5)":
        HERE.parent / "2026-12-01-visible-anchor" / "results" / "second_look_size_iou0.5",
    "– and one head, one person (0.05)": HERE / "results" / "union_samehead0.05",
    "– and one head, one person (0.1)": HERE / "results" / "union_samehead0.1",
    "– and one head, one person (0.2)": HERE / "results" / "union_samehead0.2",
    "one network, head and size maps beside the centre map, decoded as shipped": HERE / "results" / "both_centre_only",
    "– its head map's people it lacks, one head one person (0.1)": HERE / "results" / "both_samehead0.1",
    "the same network, the head map and the fine maps kept weighing as today's fine map, decoded as shipped":
        HERE / "results" / "budget_centre_only",
    "– its head map's people it lacks at that weight, one head one person (0.1)":
        HERE / "results" / "budget_samehead0.1",
}
HALVES = ("choosing", "confirming")


def cell(folder: Path, half: str, key) -> str:
    values = []
    for seed in range(3):
        path = folder / f"seed{seed}_{half}.json"
        values.append(key(json.loads(path.read_text())) if path.exists() else None)
    known = [value for value in values if value is not None]
    if not known:
        return "–"
    seeds = " / ".join("–" if value is None else f"{value:.3f}" for value in values)
    return f"{seeds} (**{sum(known) / len(known):.3f}**)" if len(known) == 3 else seeds


def main() -> None:
    figures = {"AP50 tracked": lambda d: d["ap50_tracked"], "AP50 each frame": lambda d: d["ap50_each_frame"],
               "recall, overlapping another": lambda d: d["recall_by_group"]["overlapping another"]["recall"]}
    for name, key in figures.items():
        print(f"\n{name}, seeds 0 / 1 / 2 (mean)\n")
        print("| arm | choosing (1–90) | confirming (91–179) |\n|---|---|---|")
        for arm, folder in ARMS.items():
            print(f"| {arm} | " + " | ".join(cell(folder, half, key) for half in HALVES) + " |")


if __name__ == "__main__":
    main()
