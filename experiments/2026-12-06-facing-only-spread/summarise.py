"""results/summary.md from results/pose.jsonl (this compile's arms) and facing-ensemble's distilled_*.jsonl (the
probe's three compiles): the facing model's own seed-to-seed spread, the distilled classifier's difference from the
single one, and the probe called with that difference's spread (frozen experiment, issue 57 items 1 and 4).

    python summarise.py
"""

from __future__ import annotations

import json
import math
import statistics
from pathlib import Path

HERE = Path(__file__).parent
PROBE = HERE.parent / "2026-12-05-facing-ensemble" / "results"
HALVES = ("choosing", "confirming")
MODES = ("each frame", "tracked")


def rows(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def overall(row: dict, name: str, mode: str) -> float:
    return row["readings"][f"{name}, {mode}"]["overall"]


def main() -> None:
    arms = rows(HERE / "results" / "pose.jsonl")
    seeds = sorted({int(name[len("single"):]) for name in arms[0]["bundles"] if name.startswith("single")})
    lines = ["# The facing model trained again alone: its spread, and the distilled classifier's difference", "",
             f"TUD-Stadtmitte, one compile (seed {arms[0]['seed']}), its facing model trained again from seeds "
             f"{', '.join(map(str, seeds))}; pose agreement with YOLO11n-pose @1280.", ""]
    spreads: dict[tuple[str, str], tuple[float, int]] = {}
    for which, row in enumerate(arms):
        lines += [f"## {HALVES[which]} half (frames {row['frames'][0]}-{row['frames'][1]})", "",
                  "| seed T | mode | single | distilled | difference |", "|---|---|---|---|---|"]
        for mode in MODES:
            singles = [overall(row, f"single{t}", mode) for t in seeds]
            distilled = [overall(row, f"distilled{t}", mode) for t in seeds]
            differences = [b - a for a, b in zip(singles, distilled, strict=True)]
            for t, a, b, d in zip(seeds, singles, distilled, differences, strict=True):
                lines.append(f"| {t} | {mode} | {a:.3f} | {b:.3f} | {d:+.3f} |")
            sd_difference = statistics.stdev(differences)
            spreads[HALVES[which], mode] = (sd_difference, len(differences) - 1)
            lines.append(f"| **mean (sd)** | {mode} | **{statistics.mean(singles):.3f}** "
                         f"({statistics.stdev(singles):.3f}) | **{statistics.mean(distilled):.3f}** "
                         f"({statistics.stdev(distilled):.3f}) | **{statistics.mean(differences):+.3f}** "
                         f"({sd_difference:.3f}) |")
        same = overall(row, "shipped", "each frame") == overall(row, f"single{arms[0]['seed']}", "each frame")
        lines += ["", f"The compile's own bundle and single{arms[0]['seed']} read the same: {same}.", ""]
    lines += ["## The probe's three compiles called with the difference's spread", "",
              "Per half and mode: the probe's differences (seeds 0 / 1 / 2), their mean; the spread of one "
              "difference pooled from this compile's training seeds and the probe's three compiles around their "
              "mean; the band, twice the standard error of a mean of three.", "",
              "| camera | half | mode | differences | mean | pooled sd (dof) | band | call |",
              "|---|---|---|---|---|---|---|---|"]
    for camera in ("tud", "pets"):
        probe = rows(PROBE / f"distilled_{camera}.jsonl")
        for which, half in enumerate(HALVES):
            for mode in MODES:
                first = {"tud": (1, 91), "pets": (1, 201)}[camera][which]
                chosen = sorted((r for r in probe if r["frames"][0] == first), key=lambda r: r["seed"])
                differences = [overall(r, "distilled", mode) - overall(r, "shipped", mode) for r in chosen]
                mean = statistics.mean(differences)
                within, dof = spreads[half, mode]
                between = statistics.stdev(differences)
                if camera == "tud":
                    pooled = math.sqrt((within ** 2 * dof + between ** 2 * 2) / (dof + 2))
                    pooled_dof = dof + 2
                else:
                    pooled, pooled_dof = between, 2
                band = 2 * pooled / math.sqrt(len(differences))
                call = "gain" if mean > band else "loss" if mean < -band else "level"
                lines.append(f"| {camera} | {half} | {mode} | {' / '.join(f'{d:+.3f}' for d in differences)} | "
                             f"{mean:+.3f} | {pooled:.3f} ({pooled_dof}) | ±{band:.3f} | {call} |")
    (HERE / "results" / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
