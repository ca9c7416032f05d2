"""The table of decision record 0026 from run.sh's reports (frozen).

    PYTHONPATH=. python experiments/2026-11-30-camera-roll/summarise.py OUT --out results/roll.json

Per arm (``read``: the runtime reads and undoes a roll; ``before``: d36b786's), camera and roll: the bundle's AP50
on the rolled frames and as recorded, YOLO11n-pose @1280's, the bundle's false people on the rolled empty background
(at its operating point and every one reported) and the frames' fitness states."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

OURS, YOLO = "visual compiler", "yolo11n-pose-1280.onnx @1280"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("folder", type=Path)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    rows = []
    for report_path in sorted(args.folder.glob("*/*/robustness.json")):
        report = json.loads(report_path.read_text())
        by_key = {row["key"]: row for row in report["conditions"]}
        rolled, clean = by_key["roll"], by_key["clean"]
        false_people = rolled["false_people"]
        rows.append({
            "arm": report_path.parent.parent.name, "camera": report["scene"],
            "roll_deg": rolled["parameters"]["roll_deg"],
            "ap50": round(rolled["ap50"][OURS], 3), "ap50_as_recorded": round(clean["ap50"][OURS], 3),
            "yolo_ap50": round(rolled["ap50"][YOLO], 3),
            "false_people_at_operating_point": false_people[f"{OURS} at its operating point"],
            "false_people_every_one_reported": false_people[f"{OURS}, every person reported"],
            "fitness_states": rolled["fitness_states"], "command": report["command"]})
    rows.sort(key=lambda row: (row["camera"], row["roll_deg"], row["arm"]))
    args.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("| camera | roll | arm | AP50 (as recorded) | YOLO | false people (every one) | states |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        states = ", ".join(f"{state} {count}" for state, count in row["fitness_states"].items())
        print(f"| {row['camera']} | {row['roll_deg']:g} | {row['arm']} | {row['ap50']:.3f} "
              f"({row['ap50_as_recorded']:.3f}) | {row['yolo_ap50']:.3f} | "
              f"{row['false_people_at_operating_point']} ({row['false_people_every_one_reported']}) | {states} |")


if __name__ == "__main__":
    main()
