"""The camera range on PETS09's choosing and confirming halves, three compile seeds: one table from the robustness
benchmark's reports (frozen experiment, issue 62).

    python experiments/2026-11-28-camera-range/summarise.py   # reads results/*/robustness.json
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
OURS = "visual compiler"
FAMILIES = ("camera life", "COCO-C")


def _row(report: dict) -> dict:
    clean = next(row for row in report["conditions"] if row["family"] == "clean")
    families = report["families"]
    row = {"clean": clean["ap50"][OURS]}
    for family in FAMILIES:
        row[f"{family} mPC"] = families[family]["mPC"][OURS]
        row[f"{family} rPC"] = families[family]["rPC"][OURS]
        row[f"{family} false people"] = families[family]["false_people_per_frame"][
            f"{OURS} at its operating point"]
    external = report.get("external")
    if external:
        row["YOLO clean"] = clean["ap50"][external]
        for family in FAMILIES:
            row[f"YOLO {family} rPC"] = families[family]["rPC"][external]
    return row


def main() -> None:
    reports = {path.parent.name: json.loads(path.read_text()) for path in sorted(RESULTS.glob("*/robustness.json"))}
    rows = {name: _row(report) for name, report in reports.items()}
    columns = list(dict.fromkeys(key for row in rows.values() for key in row))
    lines = ["| run | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for name, row in rows.items():
        lines.append(f"| {name} | " + " | ".join("—" if row.get(c) is None else f"{row[c]:.3f}" for c in columns)
                     + " |")
    for half in sorted({name.split("_", 1)[1] for name in rows}):
        chosen = [row for name, row in rows.items() if name.endswith(half)]
        lines.append(f"| mean of {half} ({len(chosen)} seeds) | " + " | ".join(
            f"{np.mean([row[c] for row in chosen if row.get(c) is not None]):.3f}"
            if any(row.get(c) is not None for row in chosen) else "—" for c in columns) + " |")
    text = "\n".join(lines) + "\n"
    (RESULTS / "camera_range_halves.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
