"""Pose agreement of the winter bundles with their own facing model and with one over standardised crops, seed by
seed, on TUD-Stadtmitte's halves, and how each facing model reads the truth's boxes (frozen experiment).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
WINTER = HERE.parent / "2026-12-04-winter-clothing" / "results" / "pose.jsonl"
HALVES = {1: "choosing", 91: "confirming"}


def _readings(path: Path, arm: str) -> dict[tuple[int, str, str], float]:
    """(seed, half, mode) -> pose agreement of ``arm`` on TUD-Stadtmitte."""
    out = {}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        if row["camera"] == "tud" and arm in row["bundles"]:
            for mode in ("each frame", "tracked"):
                out[(row["seed"], HALVES[row["frames"][0]], mode)] = row["readings"][f"{arm}, {mode}"]["overall"]
    return out


def main() -> None:
    winter, standardised = _readings(WINTER, "winter"), _readings(HERE / "results" / "pose.jsonl", "standardised")
    print("| seed | half | each frame: winter → standardised | tracked: winter → standardised |")
    print("|---|---|---|---|")
    for key in sorted({(seed, half) for seed, half, _ in standardised}):
        cells = [f"{winter[(*key, mode)]:.3f} → {standardised[(*key, mode)]:.3f}" for mode in ("each frame", "tracked")]
        print(f"| {key[0]} | {key[1]} | {cells[0]} | {cells[1]} |")
    for half in HALVES.values():
        cells = []
        for mode in ("each frame", "tracked"):
            seeds = sorted(seed for seed, h, m in standardised if h == half and m == mode)
            before = np.mean([winter[(seed, half, mode)] for seed in seeds])
            after = np.mean([standardised[(seed, half, mode)] for seed in seeds])
            ahead = sum(standardised[(seed, half, mode)] > winter[(seed, half, mode)] for seed in seeds)
            cells.append(f"{before:.3f} → **{after:.3f}** ({ahead} of {len(seeds)} ahead)")
        print(f"| mean | {half} | {cells[0]} | {cells[1]} |")
    print("\n| seed | half | share of the truth's clear people read the reference's way: mixed / winter / "
          "standardised |")
    print("|---|---|---|")
    for path in sorted((HERE / "results").glob("facing_real_seed*.json")):
        seed = int(path.stem.removeprefix("facing_real_seed"))
        for half, report in json.loads(path.read_text()).items():
            right = report["right"]
            print(f"| {seed} | {half} ({report['people']}) | {right['mixed']:.3f} / {right['winter']:.3f} / "
                  f"{right['standardised']:.3f} |")


if __name__ == "__main__":
    main()
