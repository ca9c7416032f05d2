"""The people-in-front arm's table against its control (frozen; decision 0033): per arm and half, AP50 tracked and
each frame, recall of people overlapping another, of the far band's people (r0), precision at the operating point,
MOTA and IDF1, seeds 0 / 1 / 2 with their mean; then pose agreement with YOLO11n-pose @1280.

    python summarise.py > results/summary.md

The control is ``../2026-12-01-tud-denser-crowd/results/crowd_5``: the scene as it is today (decision 0032), its
bundles measured there; the arm is ``results/in_front``.
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).parent
ARMS = {"today (0032)": HERE.parent / "2026-12-01-tud-denser-crowd" / "results" / "crowd_5",
        "in front 0.15": HERE / "results" / "in_front"}
HALVES = ("choosing", "confirming")


def _row(values: list[float]) -> str:
    return f"{' / '.join(f'{value:.3f}' for value in values)} ({sum(values) / len(values):.3f})"


def _runs(folder: Path, pattern: str) -> list[dict]:
    return [json.loads(path.read_text()) for path in sorted(folder.glob(pattern))]


def main() -> None:
    print("| arm | half | AP50 tracked | each frame | overlapping another | far band (r0) | precision | MOTA | IDF1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for half in HALVES:
        for arm, folder in ARMS.items():
            runs = _runs(folder, f"seed?_{half}.json")
            if not runs:
                continue
            columns = [[run["ap50_tracked"] for run in runs], [run["ap50_each_frame"] for run in runs],
                       [run["recall_by_group"]["overlapping another"]["recall"] for run in runs],
                       [run["recall_by_region"]["r0"]["recall"] for run in runs],
                       [run["precision"] for run in runs], [run["tracking"]["mota"] for run in runs],
                       [run["tracking"]["idf1"] for run in runs]]
            print(f"| {arm} | {half} | " + " | ".join(_row(column) for column in columns) + " |")
    print()
    print("| arm | half | pose agreement, tracked | each frame |")
    print("|---|---|---|---|")
    for half in HALVES:
        for arm, folder in ARMS.items():
            runs = _runs(folder, f"pose_seed?_{half}.json")
            if runs:
                print(f"| {arm} | {half} | {_row([run['visual compiler'] for run in runs])} | "
                      f"{_row([run['visual compiler, each frame on its own'] for run in runs])} |")


if __name__ == "__main__":
    main()
