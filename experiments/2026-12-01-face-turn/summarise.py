"""results/arms.jsonl as the decision record's table: pose agreement each frame and tracked, control and face turn,
per camera and half, the mean over the seeds measured with each seed's change.

    python experiments/2026-12-01-face-turn/summarise.py results/arms.jsonl > results/summary.md
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np


def main() -> None:
    rows = [json.loads(line) for line in open(sys.argv[1])]
    groups: dict[tuple[str, str], list[dict]] = defaultdict(list)
    for row in rows:
        groups[(row["camera"], "choosing" if row["frames"][0] == 1 else "confirming")].append(row)
    print("| camera | half | seeds | reading | control | face turn | change per seed | nose: control → face turn |")
    print("|---|---|---|---|---|---|---|---|")
    for (camera, half), group in sorted(groups.items()):
        for mode in ("each frame", "tracked"):
            control = [row[f"control, {mode}"]["overall"] for row in group]
            turned = [row[f"face turn, {mode}"]["overall"] for row in group]
            nose = [(row[f"control, {mode}"]["per_keypoint"]["nose"], row[f"face turn, {mode}"]["per_keypoint"]["nose"])
                    for row in group]
            changes = " / ".join(f"{b - a:+.3f}" for a, b in zip(control, turned, strict=True))
            print(f"| {camera} | {half} | {','.join(str(row['seed']) for row in group)} | {mode} | "
                  f"{np.mean(control):.3f} | {np.mean(turned):.3f} | {changes} | "
                  f"{np.mean([a for a, _ in nose]):.2f} → {np.mean([b for _, b in nose]):.2f} |")
    print()
    print("The facing read alike by both arms (largest difference of any pair's handedness): "
          + ", ".join(f"{row['camera']}{row['seed']} {row['pair_handedness_max_difference']}" for row in rows))
    print()
    print("The face turn on its own held-out renders (mean error; share of profiles read pointing the right way; "
          "seconds to train):")
    seen = set()
    for row in rows:
        key = (row["camera"], row["seed"])
        if key in seen:
            continue
        seen.add(key)
        turn = row["face_turn"]
        print(f"- {row['camera']} seed {row['seed']}: {turn['held_out_error']:.3f}, "
              f"{turn['held_out_profile_sign']:.3f}, {turn['seconds']:.0f} s ({turn['train_crops']} crops)")


if __name__ == "__main__":
    main()
