"""0053 (winter coats against the `mixed` wardrobe) called on six seeds, as 0056 asks where three leave a change
level (frozen experiment, issue 57).

`winter`'s six: the scene as it ships, seeds 0-2 (results-as-shipped), and winter-clothing's copy of it, seeds 0-2,
another draw, standing for seeds 3-5. `mixed`'s six: winter-clothing's seeds 0-2 and this experiment's seeds 3-5
(``measure.py --arm mixed``). A retrained change's seeds do not pair (0056), so which of winter's draws meets which of
mixed's seeds does not matter.

    PYTHONPATH=../.. python six_seeds_0053.py      # writes results/six_seeds_0053.md
"""

from __future__ import annotations

from pathlib import Path

from spread import CAMERA_NAMES, HALVES, RESULTS, SHIPPED, WINTER, box_runs

from benchmarks.protocol import Change, difference

FIGURES = ("AP50 tracked", "AP50 each frame")


def six(first: Path, second: Path) -> dict:
    """Seeds 0-2 from ``first`` and 3-5 from ``second`` (its seeds 0-2 or 3-5)."""
    later = {(seed % 3 + 3, half): run for (seed, half), run in box_runs(second).items()}
    return box_runs(first) | later


def main() -> None:
    lines = ["# 0053 on six seeds: `winter` against `mixed` (0056's band; choosing / confirming half)", ""]
    for camera, name in CAMERA_NAMES.items():
        winter = six(SHIPPED / camera, WINTER / f"{camera}_winter")
        mixed = six(WINTER / f"{camera}_mixed", RESULTS / "mixed" / camera)
        seeds = sorted({seed for seed, _ in mixed} & {seed for seed, _ in winter})
        lines += [f"## {name}: seeds {', '.join(map(str, seeds))}", "",
                  "| figure | half | mixed | winter | difference | level within | call |", "|---" * 7 + "|"]
        for figure in FIGURES:
            for half in HALVES:
                replaced = [mixed[seed, half][figure] for seed in seeds]
                changed = [winter[seed, half][figure] for seed in seeds]
                called = difference(Change.RETRAINED, figure, camera, half, replaced, changed)
                lines.append(f"| {figure} | {half} | {sum(replaced) / len(seeds):.3f} | "
                             f"{sum(changed) / len(seeds):.3f} | {called.mean:+.3f} | ±{called.level_within:.3f} | "
                             f"{called.call} |")
        lines.append("")
    (RESULTS / "six_seeds_0053.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
