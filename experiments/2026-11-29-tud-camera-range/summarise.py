"""The camera range on TUD-Stadtmitte's first (choosing) and second (confirming) halves: compiles with the range
(seeds 0-2) and one without it (seed 0), one table from the robustness benchmark's reports (frozen experiment,
issue 62).

    python experiments/2026-11-29-tud-camera-range/summarise.py   # reads results/*/robustness.json
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
OURS = "visual compiler"
#: The camera-range experiment's table row (clean, mPC, rPC and false people per family, YOLO's rPC), reused as it is.
_CAMERA_RANGE = importlib.util.spec_from_file_location(
    "camera_range_summary", Path(__file__).parent.parent / "2026-11-28-camera-range" / "summarise.py")
camera_range_summary = importlib.util.module_from_spec(_CAMERA_RANGE)
_CAMERA_RANGE.loader.exec_module(camera_range_summary)


def _row(report: dict) -> dict:
    """The camera-range experiment's row, with YOLO's mPC beside its rPC."""
    row = camera_range_summary._row(report)
    external = report.get("external")
    if external:
        for family in camera_range_summary.FAMILIES:
            row[f"YOLO {family} mPC"] = report["families"][family]["mPC"][external]
    return row


def _per_condition(reports: dict[str, dict]) -> list[str]:
    names = list(reports)
    keys = [row["key"] for row in next(iter(reports.values()))["conditions"] if row.get("ap50")]
    lines = ["| condition | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for key in keys:
        cells = []
        for report in reports.values():
            row = next(row for row in report["conditions"] if row["key"] == key)
            states = ", ".join(f"{state} {count}" for state, count in row.get("fitness_states", {}).items())
            cells.append(f"{row['ap50'][OURS]:.3f} ({states})")
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    return lines


def main() -> None:
    reports = {path.parent.name: json.loads(path.read_text()) for path in sorted(RESULTS.glob("*/robustness.json"))}
    rows = {name: _row(report) for name, report in reports.items()}
    columns = list(dict.fromkeys(key for row in rows.values() for key in row))
    lines = ["| run | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for name, row in rows.items():
        lines.append(f"| {name} | " + " | ".join(f"{row[key]:.3f}" if key in row else "—" for key in columns) + " |")
    lines += ["", "AP50 per condition (the bundle's fitness states over the frames):", ""] + _per_condition(reports)
    (RESULTS / "tud_halves.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
