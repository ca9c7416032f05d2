"""Pose agreement of each facing model in the winter bundles, beside the two compiles' own (frozen experiment).

    python summarise.py > results/summary.md

Reads ``results/pose.jsonl`` (``knits``, ``fifth``) and the winter-clothing experiment's ``pose.jsonl`` (``mixed``,
``winter``) and ``pose_hybrids.jsonl`` (``winter_mixed_facing``: the seed's whole default-wardrobe facing model).
"""

from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
WINTER = HERE.parent / "2026-12-04-winter-clothing" / "results"
ARMS = ("mixed", "winter", "winter_mixed_facing", "knits", "fifth")
HALVES = {1: "choosing", 91: "confirming", 201: "confirming"}


def readings() -> dict[tuple[str, str, str, int], dict[str, float]]:
    """(camera, arm, half, seed) -> {"each frame": agreement, "tracked": agreement}."""
    found: dict[tuple[str, str, str, int], dict[str, float]] = {}
    for path in (WINTER / "pose.jsonl", WINTER / "pose_hybrids.jsonl", HERE / "results" / "pose.jsonl"):
        for line in path.read_text().splitlines():
            row = json.loads(line)
            half = HALVES[row["frames"][0]]
            for name, reading in row["readings"].items():
                arm, how = name.split(", ")
                if arm in ARMS:
                    found.setdefault((row["camera"], arm, half, row["seed"]), {})[how] = reading["overall"]
    return found


def main() -> None:
    found = readings()
    print("| camera | half | facing model in the bundle | seeds | pose each frame (seeds) | tracked (seeds) |")
    print("|---|---|---|---|---|---|")
    for camera in ("tud", "pets"):
        for half in ("choosing", "confirming"):
            for arm in ARMS:
                by_seed = {seed: value for (c, a, h, seed), value in found.items() if (c, a, h) == (camera, arm, half)}
                if not by_seed:
                    continue
                seeds = sorted(by_seed)
                cells = defaultdict(list)
                for seed in seeds:
                    for how in ("each frame", "tracked"):
                        cells[how].append(by_seed[seed][how])
                text = [f"{sum(v) / len(v):.3f} ({' / '.join(f'{x:.3f}' for x in v)})" for v in cells.values()]
                print(f"| {camera} | {half} | {arm} | {', '.join(map(str, seeds))} | {text[0]} | {text[1]} |")


if __name__ == "__main__":
    main()
