"""The earlier experiments' variants called again under the band ``benchmarks.protocol`` now uses (frozen
experiment, issue 57): each camera-half's mean difference in AP50 tracked, called a gain, level or loss within 0.002
(decision 0019) and within twice its standard error (0056), and whether the rule keeps it.

    PYTHONPATH=../.. python verdicts.py      # after collect.py; writes results/verdicts.md
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from benchmarks.protocol import HALVES, Change, Difference, difference, kept

RESULTS = Path(__file__).parent / "results"
FIGURE = "AP50 tracked"
CHANGES = {"decode": Change.READ, "train": Change.RETRAINED, "render": Change.RETRAINED}
TODAY_LEVEL = 0.002


def calls(variant: pd.DataFrame, change: Change) -> list[tuple[Difference, Difference]]:
    """Each camera-half measured on two or more seeds: (within 0.002, within two standard errors)."""
    called = []
    for (camera, half), rows in variant.groupby(["camera", "half"]):
        if len(rows) < 2:
            continue
        rows = rows.sort_values("seed")
        banded = difference(change, FIGURE, camera, half, list(rows["baseline"]), list(rows["value"]))
        called.append((Difference(camera, half, banded.mean, TODAY_LEVEL), banded))
    return called


def main() -> None:
    pairs = pd.read_csv(RESULTS / "pairs.csv")
    pairs = pairs[pairs["figure"] == "ap50_tracked"]
    lines = ["# Earlier variants called again (AP50 tracked, mean of the seeds measured)", "",
             "Each cell: mean difference, then its call within 0.002 → within two standard errors of the seeds' "
             "spread. Only camera-halves with two or more seeds.", "",
             "| experiment | variant | kind | " + " | ".join(f"{c} {h}" for c in ("PETS09", "TUD") for h in HALVES)
             + " | kept: 0019 → 0056 |", "|---|---|---|---|---|---|---|---|"]
    changed_calls = total_calls = 0
    for (experiment, variant, kind), rows in pairs.groupby(["experiment", "variant", "kind"], sort=True):
        called = calls(rows, CHANGES[kind])
        if not called:
            continue
        cells = {}
        for today, banded in called:
            cells[today.camera, today.half] = f"{today.mean:+.3f} {today.call} → {banded.call}"
            changed_calls += today.call != banded.call
            total_calls += 1
        row = [cells.get((camera, half), "–") for camera in ("pets", "tud") for half in HALVES]
        verdict = " → ".join("yes" if kept(band) else "no" for band in zip(*called, strict=True))
        lines.append(f"| {experiment} | {variant} | {kind} | " + " | ".join(row) + f" | {verdict} |")
    lines += ["", f"{changed_calls} of {total_calls} camera-half calls change.", ""]
    (RESULTS / "verdicts.md").write_text("\n".join(lines))
    print("\n".join(lines[-2:]))


if __name__ == "__main__":
    main()
