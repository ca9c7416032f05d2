"""The weather and gain ranges on PETS09's choosing and confirming halves (three compile seeds) and on
TUD-Stadtmitte's first and second halves (three seeds): one table per camera from the robustness benchmark's reports,
as shipped (``unfit: suppress``) and for the networks alone (``flag``, under ``results/flag/``), and AP50 per
condition (frozen experiment, issue 62).

    python experiments/2026-11-29-weather-and-gain/summarise.py   # reads results/{pets,tud}/**/robustness.json
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
OURS = "visual compiler"
#: The TUD camera-range experiment's table row (clean, mPC, rPC and false people per family, YOLO's mPC and rPC),
#: reused as it is.
_TUD = importlib.util.spec_from_file_location(
    "tud_camera_range_summary", Path(__file__).parent.parent / "2026-11-29-tud-camera-range" / "summarise.py")
tud_summary = importlib.util.module_from_spec(_TUD)
_TUD.loader.exec_module(tud_summary)
_row = tud_summary._row


def _table(reports: dict[str, dict]) -> list[str]:
    rows = {name: _row(report) for name, report in reports.items()}
    columns = list(dict.fromkeys(key for row in rows.values() for key in row))
    lines = ["| run | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for name, row in rows.items():
        lines.append(f"| {name} | " + " | ".join("—" if row.get(c) is None else f"{row[c]:.3f}" for c in columns)
                     + " |")
    for half in sorted({name.rsplit("_", 1)[1] for name in rows if "_" in name}):
        chosen = [row for name, row in rows.items() if name.endswith(f"_{half}")]
        lines.append(f"| mean of {half} ({len(chosen)} seeds) | " + " | ".join(
            f"{np.mean([row[c] for row in chosen if row.get(c) is not None]):.3f}"
            if any(row.get(c) is not None for row in chosen) else "—" for c in columns) + " |")
    return lines


def _per_condition(reports: dict[str, dict]) -> list[str]:
    names = list(reports)
    keys = [row["key"] for row in next(iter(reports.values()))["conditions"] if row.get("ap50")]
    lines = ["| condition | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for key in keys:
        cells = []
        for report in reports.values():
            row = next(row for row in report["conditions"] if row["key"] == key)
            states = ", ".join(f"{state} {count}" for state, count in row.get("fitness_states", {}).items())
            false = row["false_people"][f"{OURS} at its operating point"]
            cells.append(f"{row['ap50'][OURS]:.3f} ({states}; {false} false)")
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    return lines


def _reports(folder: Path) -> dict[str, dict]:
    return {path.parent.name: json.loads(path.read_text()) for path in sorted(folder.glob("*/robustness.json"))}


def main() -> None:
    for camera in ("pets", "tud"):
        shipped, alone = _reports(RESULTS / camera), _reports(RESULTS / camera / "flag")
        if not shipped:
            continue
        lines = ["As shipped (`unfit: suppress`):", ""] + _table(shipped)
        if alone:
            lines += ["", "The networks alone (`unfit: flag`):", ""] + _table(alone)
        lines += ["", "AP50 per condition as shipped (the bundle's fitness states over the frames; false people on "
                      "the empty background):", ""] + _per_condition(shipped)
        text = "\n".join(lines) + "\n"
        (RESULTS / f"{camera}_halves.md").write_text(text)
        print(text)


if __name__ == "__main__":
    main()
