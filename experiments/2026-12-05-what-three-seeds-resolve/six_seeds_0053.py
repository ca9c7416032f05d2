"""0053 (winter coats against the `mixed` wardrobe) called on six seeds, as 0056 asks where three leave a change
level (frozen experiment, issue 57).

`winter`'s six: the scene as it ships, seeds 0-2 (results-as-shipped), and winter-clothing's copy of it, seeds 0-2,
another draw, standing for seeds 3-5. `mixed`'s six: winter-clothing's seeds 0-2 and this experiment's seeds 3-5
(``measure.py --arm mixed``; pose by the keypoint-capacity experiment's ``measure.py``, ``results/mixed/pose_*.jsonl``).
AP50 and pose are called under 0056's band; the miss analysis's recalls and the MOT figures, which have no measured
spread, are given as means. A retrained change's seeds do not pair (0056), so which of winter's draws meets which of
mixed's seeds does not matter.

    PYTHONPATH=../.. python six_seeds_0053.py      # writes results/six_seeds_0053.md
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from spread import CAMERA_NAMES, FIGURES, HALVES, RESULTS, SHIPPED, WINTER, add_pose, box_runs

from benchmarks.protocol import Change, difference

#: The miss analysis's and the tracker's figures, read from measure.py's results beside AP50.
MEANS = {"people overlapping another": lambda run: run["recall_by_group"]["overlapping another"]["recall"],
         "people 100 px and taller": lambda run: run["recall_by_height"][">= 100 px"]["recall"],
         "MOTA": lambda run: run["tracking"]["mota"], "IDF1": lambda run: run["tracking"]["idf1"]}


def runs(folder: Path, pose: Path, camera: str, arm: str) -> dict:
    """AP50 (and the figures of :data:`MEANS`) from ``folder``, pose agreement from ``pose``, by seed and half."""
    read = add_pose(box_runs(folder), pose, camera, arm) if pose.exists() else box_runs(folder)
    for path in folder.glob("seed*_*.json"):
        seed, half = path.stem.removeprefix("seed").split("_")
        result = json.loads(path.read_text())
        read[int(seed), half].update({name: figure(result) for name, figure in MEANS.items()})
    return read


def six(first: dict, second: dict) -> dict:
    """Seeds 0-2 from ``first`` and 3-5 from ``second`` (its seeds 0-2 or 3-5)."""
    return first | {(seed % 3 + 3, half): run for (seed, half), run in second.items()}


def main() -> None:
    lines = ["# 0053 on six seeds: `winter` against `mixed` (0056's band; choosing / confirming half)", ""]
    for camera, name in CAMERA_NAMES.items():
        winter = six(runs(SHIPPED / camera, SHIPPED / f"pose_{camera}.jsonl", camera, "shipped"),
                     runs(WINTER / f"{camera}_winter", WINTER / "pose.jsonl", camera, "winter"))
        mixed = six(runs(WINTER / f"{camera}_mixed", WINTER / "pose.jsonl", camera, "mixed"),
                    runs(RESULTS / "mixed" / camera, RESULTS / "mixed" / f"pose_{camera}.jsonl", camera, "mixed"))
        lines += [f"## {name}", "", "| figure | half | seeds | mixed | winter | difference | level within | call |",
                  "|---" * 8 + "|"]
        for figure in (*FIGURES, *MEANS):
            for half in HALVES:
                seeds = sorted(seed for seed in range(6) if figure in mixed.get((seed, half), {})
                               and figure in winter.get((seed, half), {}))
                replaced = [mixed[seed, half][figure] for seed in seeds]
                changed = [winter[seed, half][figure] for seed in seeds]
                cells = f"| {figure} | {half} | {len(seeds)} | {np.mean(replaced):.3f} | {np.mean(changed):.3f} |"
                if figure in MEANS:
                    lines.append(f"{cells} {np.mean(changed) - np.mean(replaced):+.3f} | – | – |")
                    continue
                called = difference(Change.RETRAINED, figure, camera, half, replaced, changed)
                lines.append(f"{cells} {called.mean:+.3f} | ±{called.level_within:.3f} | {called.call} |")
        lines.append("")
    (RESULTS / "six_seeds_0053.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
