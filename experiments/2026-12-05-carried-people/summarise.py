"""Means over the compiles of each variant and half of ``results/CAMERA.jsonl``: ``python summarise.py CAMERA``."""

from __future__ import annotations

import collections
import json
import sys
from pathlib import Path


def main() -> None:
    camera = sys.argv[1]
    rows = [json.loads(line) for line in (Path(__file__).parent / "results" / f"{camera}.jsonl").open()]
    by_arm = collections.defaultdict(list)
    for row in rows:
        by_arm[(row["half"], row["variant"])].append(row)
    print("| half | variant | compiles | AP50 tracked (each compile) | overlapping | precision | recall | duplicates "
          "| merged |")
    print("|---|---|---|---|---|---|---|---|---|")
    for (half, variant), arm in sorted(by_arm.items()):
        def mean(value, arm=arm) -> float:
            return sum(value(row) for row in arm) / len(arm)
        each = " / ".join(f"{row['ap50_tracked']:.3f}" for row in sorted(arm, key=lambda r: (r["compile"], r["seed"])))
        print(f"| {half} | {variant} | {len(arm)} | {mean(lambda r: r['ap50_tracked']):.4f} ({each}) "
              f"| {mean(lambda r: r['recall_by_group']['overlapping another']['recall'] or 0):.3f} "
              f"| {mean(lambda r: r['precision']):.3f} | {mean(lambda r: r['recall']):.3f} "
              f"| {mean(lambda r: r['false_positives']['duplicate']):.1f} "
              f"| {mean(lambda r: r['false_positives']['merged']):.1f} |")


if __name__ == "__main__":
    main()
