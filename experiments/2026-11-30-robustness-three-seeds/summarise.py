"""The three compile seeds' robustness reports side by side (frozen, issue 62's acceptance).

    PYTHONPATH=. python experiments/2026-11-30-robustness-three-seeds/summarise.py
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPORTS = {0: HERE.parents[1] / "benchmarks/results/robustness/robustness.json",
           1: HERE / "results/robustness_seed1.json", 2: HERE / "results/robustness_seed2.json"}
OURS, YOLO = "visual compiler", "yolo11n-pose-1280.onnx @1280"
FALSE_PEOPLE = "visual compiler at its operating point"


def family(report: dict, name: str) -> dict:
    return report["families"][name]


def main() -> None:
    rows = ["| seed | clean AP50 | camera life mPC | camera life rPC | false people a frame, camera life | COCO-C rPC "
            "| YOLO's COCO-C rPC, same run | COCO-C rPC choosing / confirming |",
            "|---|---|---|---|---|---|---|---|"]
    for seed, path in REPORTS.items():
        report = json.loads(path.read_text())
        life, coco = family(report, "camera life"), family(report, "COCO-C")
        clean = next(entry for entry in report["conditions"] if entry["key"] == "clean")["ap50"][OURS]
        halves = coco["by_half"]
        rows.append(f"| {seed} | {clean:.3f} | {life['mPC'][OURS]:.3f} | {life['rPC'][OURS]:.3f} "
                    f"| {life['false_people_per_frame'][FALSE_PEOPLE]:.2f} "
                    f"| {coco['rPC'][OURS]:.4f} | {coco['rPC'][YOLO]:.4f} "
                    f"| {halves['choosing']['rPC'][OURS]:.3f} / {halves['confirming']['rPC'][OURS]:.3f} |")
    text = "\n".join(rows) + "\n"
    (HERE / "results/seeds.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
