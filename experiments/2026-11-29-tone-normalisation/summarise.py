"""Tone normalisation on PETS09's choosing and confirming halves, three compile seeds: the robustness benchmark's
reports with the frame normalised (results/) against the same bundles and frames as given (the camera-range
experiment's results, measured before the runtime normalised; frozen experiment, issue 62).

    python experiments/2026-11-29-tone-normalisation/summarise.py   # writes results/tone_halves.md
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
NORMALISED = HERE / "results"
AS_GIVEN = HERE.parent / "2026-11-28-camera-range" / "results"
OURS = "visual compiler"
CAMERA_LIFE = ("exposure-2", "exposure-3", "exposure+1", "warm", "cool", "ir", "blur", "nudge")


def _load(folder: Path) -> dict[str, dict]:
    return {path.parent.name: json.loads(path.read_text()) for path in sorted(folder.glob("*/robustness.json"))}


def _ap(report: dict, key: str) -> float:
    return next(row for row in report["conditions"] if row["key"] == key)["ap50"][OURS]


def _family(report: dict, family: str, measure: str) -> float:
    return report["families"][family][measure][OURS]


def main() -> None:
    normalised, as_given = _load(NORMALISED), _load(AS_GIVEN)
    runs = [name for name in normalised if name in as_given]
    lines = ["| run | clean | camera life mPC as given → normalised | rPC | false people, camera life | "
             "COCO-C mPC | " + " | ".join(CAMERA_LIFE) + " |", "|---|" + "---|" * (5 + len(CAMERA_LIFE))]
    gains = []
    for name in runs:
        before, after = as_given[name], normalised[name]
        cells = [f"{_ap(before, 'clean'):.3f} → {_ap(after, 'clean'):.3f}",
                 f"{_family(before, 'camera life', 'mPC'):.3f} → {_family(after, 'camera life', 'mPC'):.3f}",
                 f"{_family(before, 'camera life', 'rPC'):.3f} → {_family(after, 'camera life', 'rPC'):.3f}",
                 f"{after['families']['camera life']['false_people_per_frame'][f'{OURS} at its operating point']:.2f}",
                 f"{_family(before, 'COCO-C', 'mPC'):.3f} → {_family(after, 'COCO-C', 'mPC'):.3f}"]
        cells += [f"{_ap(after, key) - _ap(before, key):+.3f}" for key in CAMERA_LIFE]
        gains.append(_family(after, "camera life", "mPC") - _family(before, "camera life", "mPC"))
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    external = {name: report["families"]["camera life"]["rPC"].get(report["external"])
                for name, report in normalised.items() if report.get("external")}
    lines += ["", f"Camera-life mPC gained {np.mean(gains):+.4f} on average (min {min(gains):+.4f}, max "
              f"{max(gains):+.4f}) over {len(gains)} runs; per-condition columns: AP50 normalised minus as given.",
              "YOLO11n-pose @1280 camera-life rPC in the same runs: "
              + ", ".join(f"{name} {value:.3f}" for name, value in external.items())]
    (NORMALISED / "tone_halves.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
