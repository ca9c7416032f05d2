"""The arms' table: pose agreement per camera, half and reading, control against the keypoint model, the mean of the
seeds and each seed's change; the limbs; the time a frame takes (frozen).

    python experiments/2026-12-01-keypoint-crops/summarise.py results/arms.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

HALVES = {1: "choosing", 91: "confirming", 201: "confirming"}
LIMBS = ("elbow", "wrist", "knee", "ankle")
ARMS = ("control", "keypoint model", "keypoint model, the networks' wrists and ankles")


def main() -> None:
    latest = {}
    for line in open(sys.argv[1]):  # a half read again (seed 0 with the third reading) replaces its first reading
        row = json.loads(line)
        latest[(row["camera"], row["seed"], row["frames"][0])] = row
    rows = list(latest.values())
    table: dict[tuple, dict[str, list]] = defaultdict(lambda: defaultdict(list))
    times: dict[tuple, list] = defaultdict(list)
    for row in rows:
        half = HALVES[row["frames"][0]]
        for reading in ("each frame", "tracked"):
            key = (row["camera"], half, reading)
            for arm in ARMS:
                entry = row.get(f"{arm}, {reading}")
                if entry is None:
                    continue
                table[key][arm].append(entry["overall"])
                limbs = [value for name, value in entry["per_keypoint"].items() if name.split("_")[-1] in LIMBS]
                table[key][f"{arm} limbs"].append(float(np.mean(limbs)))
            table[key]["seeds"].append(row["seed"])
        times[(row["camera"], half)].append((row["time_ratio"], row["median_ms_a_frame"],
                                             row["frames_whose_boxes_differ"]))
    print("| camera | half | reading | seeds | arm | pose agreement | change per seed | limbs |")
    print("|---|---|---|---|---|---|---|---|")
    for (camera, half, reading), values in table.items():
        control = np.array(values["control"])
        for arm in ARMS:
            if len(values[arm]) != len(control):
                continue
            changes = " / ".join(f"{change:+.3f}" for change in np.array(values[arm]) - control)
            print(f"| {camera} | {half} | {reading} | {', '.join(map(str, values['seeds']))} | {arm} | "
                  f"{np.mean(values[arm]):.3f} | {changes if arm != 'control' else ''} | "
                  f"{np.mean(values[f'{arm} limbs']):.2f} |")
    print()
    print("| camera | half | time a frame, keypoint model / control (each seed) | median ms a frame (control, model) | "
          "frames whose boxes differ |")
    print("|---|---|---|---|---|")
    for (camera, half), entries in times.items():
        ratios = " / ".join(f"{ratio:.2f}x" for ratio, _, _ in entries)
        medians = "; ".join(f"{ms['control']:.1f}, {ms['keypoint model']:.1f}" for _, ms, _ in entries)
        print(f"| {camera} | {half} | {ratios} | {medians} | {sum(differ for _, _, differ in entries)} |")


if __name__ == "__main__":
    main()
