"""``results/summary.md`` from ``results/carried.jsonl`` (diagnose.py) and ``results/tud.jsonl`` (measure.py).

    python summarise.py
"""

from __future__ import annotations

import collections
import json
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
FEATURES = {"seen_iou_now": "IoU with the seen person overlapping it most",
            "feet_below": "that person's feet below its own (its heights)",
            "height_ratio": "that person's height over its own",
            "most_beside": "most its track's box overlapped another seen person's (IoU)",
            "born_beside": "its track's first box overlapping a seen person (IoU)",
            "age_s": "its track's age (s)", "unseen_s": "time unseen (s)", "score": "score"}


def lines() -> list[str]:
    rows = [json.loads(line) for line in (RESULTS / "carried.jsonl").read_text().splitlines()]
    counts = collections.Counter(row["kind"] for row in rows)
    out = ["# Carried people, TUD-Stadtmitte's choosing half, six compiles (diagnose.py)", "",
           f"hidden {counts['hidden']}, duplicate {counts['duplicate']}, false {counts['false']}; "
           "median (quartiles)", "", "| feature | hidden | duplicate | false |", "|---|---|---|---|"]
    for feature, name in FEATURES.items():
        cells = []
        for kind in ("hidden", "duplicate", "false"):
            values = [row[feature] for row in rows if row["kind"] == kind and row[feature] is not None]
            cells.append(f"{np.median(values):.2f} ({np.percentile(values, 25):.2f}–{np.percentile(values, 75):.2f})")
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    measured = [json.loads(line) for line in (RESULTS / "tud.jsonl").read_text().splitlines()]
    by_variant: dict[str, dict[str, dict]] = collections.defaultdict(dict)
    for row in measured:
        by_variant[row["variant"]][row["compile"]] = row
    compiles = sorted(by_variant["shipped"])
    out += ["", "# AP50 tracked, TUD-Stadtmitte's choosing half (measure.py)", "",
            f"compiles: {' / '.join(compiles)}", "",
            "| variant | mean | against shipped, each compile | overlapping another | precision |",
            "|---|---|---|---|---|"]
    for variant, results in by_variant.items():
        if sorted(results) != compiles:
            continue
        ap = [results[c]["ap50_tracked"] for c in compiles]
        gains = [a - by_variant["shipped"][c]["ap50_tracked"] for a, c in zip(ap, compiles, strict=True)]
        overlapping = np.mean([results[c]["recall_by_group"]["overlapping another"]["recall"] for c in compiles])
        precision = np.mean([results[c]["precision"] for c in compiles])
        out.append(f"| {variant} | {np.mean(ap):.4f} | " + " / ".join(f"{g:+.3f}" for g in gains)
                   + f" | {overlapping:.3f} | {precision:.3f} |")
    return out


if __name__ == "__main__":
    (RESULTS / "summary.md").write_text("\n".join(lines()) + "\n")
