"""``results/summary.md``: each arm against the shipped bundles, seed by seed and called under 0056's band
(frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python summarise.py

The control is results-as-shipped's measurement of the same compiles. ``head`` and ``centre_only`` retrain r0
(``*_all``: every region), so each is called against the control as a retrained change; ``head`` against
``centre_only`` (the same networks, read another way) as a change read on the same bundles.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from benchmarks.protocol import Change, difference

HERE = Path(__file__).parent
RESULTS = HERE / "results"
SHIPPED = HERE.parent / "2026-12-05-results-as-shipped" / "results"
HALVES = ("choosing", "confirming")
CAMERAS = {"pets": "PETS09", "tud": "TUD-Stadtmitte"}
FIGURES = {"AP50 tracked": lambda run: run["ap50_tracked"], "AP50 each frame": lambda run: run["ap50_each_frame"],
           "people overlapping another": lambda run: run["recall_by_group"]["overlapping another"]["recall"],
           "people apart from others": lambda run: run["recall_by_group"]["apart"]["recall"],
           "recall at the operating point": lambda run: run["recall"],
           "precision at the operating point": lambda run: run["precision"],
           "MOTA": lambda run: run["tracking"]["mota"], "IDF1": lambda run: run["tracking"]["idf1"],
           "ms each frame (median, not comparable across runs)": lambda run: run["ms_each_frame"]}
CALLED = ("AP50 tracked", "AP50 each frame")
#: (arm, what it is called against, the kind of change).
COMPARISONS = (("centre_only", "shipped", Change.RETRAINED), ("head", "shipped", Change.RETRAINED),
               ("head", "centre_only", Change.READ), ("centre_only_all", "shipped", Change.RETRAINED),
               ("head_all", "shipped", Change.RETRAINED), ("head_all", "centre_only_all", Change.READ),
               ("head_all", "head", Change.RETRAINED))
ARMS = ("centre_only", "head", "centre_only_all", "head_all")


def runs(folder: Path) -> dict[tuple[int, str], dict]:
    found = {}
    for path in sorted(folder.glob("seed*_*.json")):
        seed, half = path.stem.removeprefix("seed").split("_")
        found[int(seed), half] = json.loads(path.read_text())
    return found


def camera_lines(camera: str) -> list[str]:
    arms = {"shipped": runs(SHIPPED / camera)} | {arm: runs(RESULTS / f"{camera}_{arm}") for arm in ARMS}
    arms = {arm: found for arm, found in arms.items() if found}
    seeds = sorted({seed for seed, _ in arms.get("head", {})} & {seed for seed, _ in arms.get("centre_only", {})})
    if not seeds:
        return []
    lines = [f"## {CAMERAS[camera]}: seeds {', '.join(map(str, seeds))}", "",
             f"| figure | half | {' | '.join(arms)} | seeds ({' / '.join(arms)}) |", "|---" * (len(arms) + 3) + "|"]
    for name, read in FIGURES.items():
        for half in HALVES:
            values = {arm: [read(arms[arm][seed, half]) for seed in seeds if (seed, half) in arms[arm]]
                      for arm in arms}
            means = " | ".join(f"{np.mean(v):.3f}" if v else "–" for v in values.values())
            each = " / ".join(", ".join(f"{x:.3f}" for x in v) for v in values.values())
            lines.append(f"| {name} | {half} | {means} | {each} |")
    lines += ["", "| change | against | figure | half | difference | level within | call |", "|---" * 7 + "|"]
    for arm, against, change in COMPARISONS:
        if arm not in arms or against not in arms:
            continue
        for name in CALLED:
            for half in HALVES:
                both = [seed for seed in seeds if (seed, half) in arms[arm] and (seed, half) in arms[against]]
                if not both:
                    continue
                called = difference(change, name, camera, half, [FIGURES[name](arms[against][s, half]) for s in both],
                                    [FIGURES[name](arms[arm][s, half]) for s in both])
                lines.append(f"| {arm} | {against} | {name} | {half} | {called.mean:+.3f} | "
                             f"±{called.level_within:.3f} | {called.call} |")
    return lines + [""]


def main() -> None:
    lines = ["# r0 with a head map, on the scenes as they ship (issue 57 item 2)", ""]
    for camera in CAMERAS:
        lines += camera_lines(camera)
    (RESULTS / "summary.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
