"""``results/summary.md`` from ``results/tud.jsonl`` and ``results/pets.jsonl``: ``python summarise.py``.

First each variant's AP50 tracked against the shipped settings on both cameras' halves (the mean difference over
the compiles measured with both, their number in brackets), then each camera's full table: every compile's figure,
people overlapping another, precision and recall at the operating point, and the false positives that are
duplicates or merged people.
"""

from __future__ import annotations

import collections
import json
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
CAMERAS = {"tud": "TUD-Stadtmitte", "pets": "PETS09"}
HALVES = ("choosing", "confirming")


def _arms(camera: str) -> dict[tuple[str, str], list[dict]]:
    path = RESULTS / f"{camera}.jsonl"
    arms = collections.defaultdict(list)
    for line in path.open() if path.exists() else []:
        row = json.loads(line)
        arms[(row["half"], row["variant"])].append(row)
    return arms


def _mean(rows: list[dict], value) -> float:
    return sum(value(row) for row in rows) / len(rows)


def _ap(row: dict) -> float:
    return row["ap50_tracked"]


def _compile(row: dict) -> tuple[str, int]:
    return row["compile"], row["seed"]


def main() -> None:
    arms = {camera: _arms(camera) for camera in CAMERAS}
    variants = sorted({variant for camera in arms.values() for _, variant in camera} - {"shipped"})
    lines = ["# AP50 tracked against the shipped settings", "",
             "| variant | " + " | ".join(f"{CAMERAS[c]} {h}" for c in CAMERAS for h in HALVES) + " |",
             "|---|" + "---|" * (len(CAMERAS) * len(HALVES)),
             "| shipped | " + " | ".join(f"{_mean(arms[c][(h, 'shipped')], _ap):.4f} ({len(arms[c][(h, 'shipped')])})"
                                        if arms[c][(h, "shipped")] else "–" for c in CAMERAS for h in HALVES) + " |"]
    for variant in variants:
        cells = []
        for camera in CAMERAS:
            for half in HALVES:
                shipped = {_compile(row): _ap(row) for row in arms[camera][(half, "shipped")]}
                paired = [_ap(row) - shipped[_compile(row)] for row in arms[camera].get((half, variant), [])
                          if _compile(row) in shipped]
                cells.append(f"{sum(paired) / len(paired):+.4f} ({len(paired)})" if paired else "–")
        lines.append(f"| {variant} | " + " | ".join(cells) + " |")
    for camera, name in CAMERAS.items():
        lines += ["", f"# {name}", "",
                  "| half | variant | compiles | AP50 tracked (each compile) | overlapping | precision | recall "
                  "| duplicates | merged |", "|---|---|---|---|---|---|---|---|---|"]
        for (half, variant), rows in sorted(arms[camera].items()):
            ordered = sorted(rows, key=lambda row: (row["compile"], row["seed"]))
            each = " / ".join(f"{_ap(row):.3f}" for row in ordered)
            lines.append(
                f"| {half} | {variant} | {len(rows)} | {_mean(rows, _ap):.4f} ({each}) "
                f"| {_mean(rows, lambda r: r['recall_by_group']['overlapping another']['recall'] or 0):.3f} "
                f"| {_mean(rows, lambda r: r['precision']):.3f} | {_mean(rows, lambda r: r['recall']):.3f} "
                f"| {_mean(rows, lambda r: r['false_positives']['duplicate']):.1f} "
                f"| {_mean(rows, lambda r: r['false_positives']['merged']):.1f} |")
    (RESULTS / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:len(variants) + 5]))


if __name__ == "__main__":
    main()
