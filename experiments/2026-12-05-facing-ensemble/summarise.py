"""results/summary.md: each arm's pose agreement with YOLO11n-pose @1280 against the bundles as shipped, per seed and
half (frozen experiment, issue 57 item 4).

    python summarise.py

The control is head-union-iou's reading of the same bundles (``results/pose_agree.jsonl``, main since 0060); an arm
measured beside the shipped bundle in one process (``rebuilt_*``) is compared with that reading.
"""

from __future__ import annotations

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
CONTROL = HERE.parent / "2026-12-05-head-union-iou" / "results" / "pose_agree.jsonl"
ARMS = {"other_seeds_tud": "three compiles' facing models averaged (other renders)",
        "same_renders_tud": "three facing models of the compile's renders averaged (seeds S, S+1000, S+2000)",
        "mirror_tud": "tall people's mirrored crop read by a second model (seed S+1000)",
        "distilled_tud": "one classifier trained to read as the three members' mean reads (distil.py)",
        "distilled_pets": "one classifier trained to read as the three members' mean reads (distil.py)",
        "rebuilt_pets": "the product's facing model, three members in one graph",
        "rebuilt_tud": "the product's facing model, three members in one graph"}
MODES = ("each frame", "tracked")


def _readings(path: Path, camera: str, skip_shipped: bool) -> dict:
    readings = {}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        if row["camera"] != camera:
            continue
        half = 0 if row["frames"][0] == 1 else 1
        readings[(row["seed"], half)] = {key.rsplit(", ", 1)[1]: value["overall"]
                                         for key, value in row["readings"].items()
                                         if not (skip_shipped and key.startswith("shipped"))}
    return readings


def main() -> None:
    lines = ["# Facing models averaged: pose agreement against the bundles as shipped", "",
             "Per seed 0 / 1 / 2, then the mean; choosing half (frames 1-90 / 1-200), then confirming.", ""]
    for arm, label in ARMS.items():
        path = HERE / "results" / f"{arm}.jsonl"
        if not path.exists():
            continue
        camera = arm.rsplit("_", 1)[1]
        control, measured = _readings(CONTROL, camera, False), _readings(path, camera, True)
        lines += [f"## {arm}: {label}", "", "| | " + " | ".join(f"{mode}, {half}" for half in ("choosing", "confirming")
                                                                    for mode in MODES) + " |", "|---" * 5 + "|"]
        for name, source in (("shipped", control), (arm, measured)):
            cells = []
            for half in (0, 1):
                for mode in MODES:
                    values = [source[(seed, half)][mode] for seed in range(3) if (seed, half) in source]
                    cells.append(" / ".join(f"{value:.3f}" for value in values)
                                 + (f", **{statistics.mean(values):.3f}**" if len(values) == 3 else ""))
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        lines.append("")
    (HERE / "results" / "summary.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
