"""How far a change's per-seed difference from what it replaces moves from seed to seed, by the kind of change
(frozen experiment, issue 57): pooled over every variant of the earlier experiments that ``collect.py`` found, each
around its own mean, so a variant's effect is not counted as noise.

    python pairs.py      # after collect.py; writes results/paired_spread.md and results/decode_noise.json

Variants whose figure equals what they replace on every seed (a facing model leaves the boxes alone; a tracker
setting that never fires) are left out: they say nothing about a change that does something.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

RESULTS = Path(__file__).parent / "results"
KINDS = ("decode", "train", "render")
CAMERAS = ("pets", "tud")
HALVES = ("choosing", "confirming")
FIGURES = ("ap50_tracked", "ap50_each", "pose_each", "pose_tracked")
KIND_NAMES = {"decode": "the same bundles read another way", "train": "networks trained again on the same renders",
              "render": "renders drawn again (scene or render settings)"}


def differences() -> pd.DataFrame:
    pairs = pd.read_csv(RESULTS / "pairs.csv")
    pairs["difference"] = pairs["value"] - pairs["baseline"]
    variant = ["experiment", "variant", "kind", "camera", "half", "figure"]
    does_something = pairs.groupby(variant)["difference"].transform(lambda d: bool((d.abs() > 1e-9).any()))
    return pairs[does_something]


def pooled(group: pd.DataFrame) -> tuple[float, int, int]:
    """The per-seed standard deviation around each variant's mean, pooled over variants with two or more seeds; its
    degrees of freedom and the variants it pools."""
    squares, dof, variants = 0.0, 0, 0
    for _, variant in group.groupby(["experiment", "variant"]):
        if len(variant) > 1:
            squares += float(variant["difference"].var(ddof=1)) * (len(variant) - 1)
            dof += len(variant) - 1
            variants += 1
    return (float(np.sqrt(squares / dof)) if dof else float("nan")), dof, variants


def half_correlation(group: pd.DataFrame) -> float:
    """The correlation of one seed's deviations on the choosing and the confirming half, over the variants measured
    on both."""
    index = ["experiment", "variant", "seed"]
    wide = group.pivot_table(index=index, columns="half", values="difference").dropna()
    if len(wide) < 3:
        return float("nan")
    deviations = wide - wide.groupby(level=["experiment", "variant"]).transform("mean")
    return float(np.corrcoef(deviations["choosing"], deviations["confirming"])[0, 1])


def main() -> None:
    data = differences()
    lines = ["# A change's per-seed difference: its spread from seed to seed, by kind", "",
             "Standard deviation of one seed's difference around its variant's mean (degrees of freedom, variants); "
             "choosing / confirming half.", "",
             "| kind | figure | PETS09 | TUD-Stadtmitte |", "|---|---|---|---|"]
    noise = {}
    for kind in KINDS:
        for figure in FIGURES:
            cells = []
            for camera in CAMERAS:
                subset = data[(data.kind == kind) & (data.camera == camera) & (data.figure == figure)]
                halves = {half: pooled(subset[subset.half == half]) for half in HALVES}
                if all(dof == 0 for _, dof, _ in halves.values()):
                    cells.append("–")
                    continue
                cells.append(" / ".join(f"{sd:.4f} ({dof}, {n})" for sd, dof, n in halves.values()))
                if kind == "decode" and figure == "ap50_tracked":
                    noise[camera] = {"choosing": halves["choosing"][0], "confirming": halves["confirming"][0],
                                     "correlation": half_correlation(subset)}
            if any(cell != "–" for cell in cells):
                lines.append(f"| {KIND_NAMES[kind]} | {figure} | " + " | ".join(cells) + " |")
    lines += ["", "Correlation of one seed's deviations on both halves, the same bundles read another way, AP50 "
              "tracked: " + ", ".join(f"{camera} {value['correlation']:+.2f}" for camera, value in noise.items()),
              ""]
    (RESULTS / "decode_noise.json").write_text(json.dumps(noise, indent=1) + "\n")
    (RESULTS / "paired_spread.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
