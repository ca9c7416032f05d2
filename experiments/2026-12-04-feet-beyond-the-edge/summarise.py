"""Today against feet kept beyond the edge, seed by seed and mean, per camera and half.

    python summarise.py > results/summary.md
"""
import json
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
print("| camera | half | AP50 tracked, today (seeds 0 / 1 / 2: mean) | edge | AP50 each frame, today | edge |")
print("|---|---|---|---|---|---|")
for camera in ("pets", "tud"):
    for half in ("choosing", "confirming"):
        cells = []
        for key in ("ap50_tracked", "ap50_each_frame"):
            for arm in ("today", "edge"):
                values = [json.loads((RESULTS / f"{camera}_{arm}" / f"seed{s}_{half}.json").read_text())[key]
                          for s in range(3)]
                cells.append(" / ".join(f"{v:.3f}" for v in values) + f": **{sum(values) / 3:.3f}**")
        print(f"| {camera} | {half} | " + " | ".join(cells) + " |")
