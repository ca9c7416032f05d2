"""results/summary.md from results/options.jsonl and results/arms.jsonl (frozen experiment, decision 0059).

    python experiments/2026-12-05-each-person-own-part/summarise.py RESULTS > RESULTS/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

HALVES = {"pets": {1: "choosing (1–200)", 201: "confirming (201–400)"},
          "tud": {1: "choosing (1–90)", 91: "confirming (91–179)"}}
OPTIONS = ("shared", "whole", "own", "stacked")


def _options(rows: list[dict]) -> None:
    print("# The keypoint model's crops cut four ways (TUD-Stadtmitte, every 6th frame, seeds 0–2)\n")
    print("| option | ms a frame (model only) | sure keypoints moved > 1 % of height | > 3 % | most moved |")
    print("|---|---|---|---|---|")
    for name in OPTIONS:
        cells = [" / ".join(f"{row[name][key]:{form}}" for row in rows) for key, form in
                 (("ms_a_frame", ".2f"), ("moved_over_1pct_height", ".4f"), ("moved_over_3pct_height", ".4f"),
                  ("most_moved_share_of_height", ".3f"))]
        print(f"| {name} | " + " | ".join(cells) + " |")
    print(f"\n{sum(row['people'] for row in rows)} people read ≥ 100 px over {sum(row['frames'] for row in rows)} "
          "frames; moved: between the person read alone and beside the frame's others, among the keypoints either "
          "reading is sure of.\n")


def _arms(rows: list[dict]) -> None:
    table: dict[tuple[str, int, str], dict[int, float]] = defaultdict(dict)
    ratios: dict[tuple[str, int], dict[int, float]] = defaultdict(dict)
    differ = 0
    for row in rows:
        first = row["frames"][0]
        for name, reading in row["readings"].items():
            table[row["camera"], first, name][row["seed"]] = reading["overall"]
        ratios[row["camera"], first][row["seed"]] = row["time_ratio"]["own part"]
        differ += row["frames_whose_boxes_differ"]
    print("# Pose agreement with YOLO11n-pose @1280, shared part → own part, seed by seed (mean)\n")
    print("| camera, half | each frame | tracked | time a frame, own / shared |")
    print("|---|---|---|---|")
    for camera, halves in HALVES.items():
        for first, label in halves.items():
            cells = []
            for mode in ("each frame", "tracked"):
                shared, own = (table[camera, first, f"{arm}, {mode}"] for arm in ("shared part", "own part"))
                change = np.mean([own[s] - shared[s] for s in shared])
                cells.append(f"{np.mean(list(shared.values())):.3f} → {np.mean(list(own.values())):.3f} "
                             f"({change:+.4f}; seeds " + ", ".join(f"{own[s] - shared[s]:+.4f}" for s in sorted(own))
                             + ")")
            seeds = ratios[camera, first]
            mean = np.mean(list(seeds.values()))
            cells.append(", ".join(f"{seeds[s]:.3f}x" for s in sorted(seeds)) + f" (**{mean:.3f}x**)")
            print(f"| {camera}, {label} | " + " | ".join(cells) + " |")
    print(f"\nFrames whose boxes differ between the arms: {differ}. Times: medians in one process, the arms read "
          "frame by frame in turn, 2 threads each, 2-core AMD EPYC.")


def main() -> None:
    results = Path(sys.argv[1])
    _options([json.loads(line) for line in open(results / "options.jsonl")])
    _arms([json.loads(line) for line in open(results / "arms.jsonl")])


if __name__ == "__main__":
    main()
