"""``results/table.md``: docs/results.md's table of the bundles' figures for the head-map compiles, as
results-as-shipped's ``summarise.py`` makes it for the shipped ones (its code, reading this experiment's results and
the head bundle's pose) (frozen experiment, issue 57 item 2).

    python table.py
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

HERE = Path(__file__).parent
_TABLE = importlib.util.spec_from_file_location(
    "shipped_table", HERE.parent / "2026-12-05-results-as-shipped" / "summarise.py")
shipped_table = sys.modules["shipped_table"] = importlib.util.module_from_spec(_TABLE)
_TABLE.loader.exec_module(shipped_table)


def head_pose(camera: str) -> dict[tuple[int, str], dict[str, float]]:
    """The head bundle's pose agreement by seed and half (``results/pose_CAMERA.jsonl``, whose lines read both)."""
    path = shipped_table.RESULTS / f"pose_{camera}.jsonl"
    pose = {}
    for line in path.read_text().splitlines() if path.exists() else []:
        record = json.loads(line)
        half = shipped_table.HALVES[shipped_table.POSE_FRAMES[camera].index(record["frames"])]
        pose[record["seed"], half] = {kind: record["readings"][f"head, {kind}"]["overall"]
                                      for kind in ("each frame", "tracked")}
    return pose


if __name__ == "__main__":
    shipped_table.RESULTS = HERE / "results"
    shipped_table._pose = head_pose
    text = ["# The head-map bundles of the scenes as they ship, mean of the seeds (choosing / confirming half)", ""]
    for camera in ("pets", "tud"):
        if (shipped_table.RESULTS / camera).exists():
            text += shipped_table.camera_table(camera)
    (shipped_table.RESULTS / "table.md").write_text("\n".join(text))
    print("\n".join(text))
