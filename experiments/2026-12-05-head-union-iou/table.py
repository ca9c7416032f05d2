"""``results/table.md``: docs/results.md's table of the bundles' figures with the heads' boxes from their keypoints
where the size map agrees (``results/agree-1.15``, decision 0060), as results-as-shipped's ``summarise.py`` makes it
(its code, reading this experiment's results and ``results/pose_agree.jsonl``) (frozen experiment, issue 57).

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
ARM = "agree-1.15"


def arm_pose(camera: str) -> dict[tuple[int, str], dict[str, float]]:
    """The arm's pose agreement by seed and half (``results/pose_agree.jsonl``, both cameras)."""
    pose = {}
    for line in (HERE / "results" / "pose_agree.jsonl").read_text().splitlines():
        record = json.loads(line)
        if record["camera"] != camera:
            continue
        half = shipped_table.HALVES[shipped_table.POSE_FRAMES[camera].index(record["frames"])]
        pose[record["seed"], half] = {kind: record["readings"][f"{ARM}, {kind}"]["overall"]
                                      for kind in ("each frame", "tracked")}
    return pose


if __name__ == "__main__":
    shipped_table.RESULTS = HERE / "results" / ARM
    shipped_table._pose = arm_pose
    text = ["# The head-map bundles with the heads' boxes from their keypoints where the size map agrees, mean of the "
            "seeds (choosing / confirming half)", ""]
    for camera in ("pets", "tud"):
        text += shipped_table.camera_table(camera)
    (HERE / "results" / "table.md").write_text("\n".join(text))
    print("\n".join(text))
