"""``results/summary.md``: docs/results.md's table of the bundle's figures (mean of the seeds measured, choosing /
confirming half), from ``results/CAMERA/seedS_HALF.json`` (measure.py) and ``results/pose_CAMERA.jsonl``, and each
seed's AP50 and pose.

    python summarise.py
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).parent / "results"
HALVES = ("choosing", "confirming")
POSE_FRAMES = {"pets": ([1, 200, 5], [201, 400, 5]), "tud": ([1, 90, 1], [91, 179, 1])}


def _runs(camera: str) -> dict[tuple[int, str], dict]:
    runs = {}
    for path in sorted((RESULTS / camera).glob("seed*_*.json")):
        seed, half = path.stem.removeprefix("seed").split("_")
        runs[int(seed), half] = json.loads(path.read_text())
    return runs


def _pose(camera: str) -> dict[tuple[int, str], dict[str, float]]:
    path = RESULTS / f"pose_{camera}.jsonl"
    pose = {}
    for line in path.read_text().splitlines() if path.exists() else []:
        record = json.loads(line)
        half = HALVES[POSE_FRAMES[camera].index(record["frames"])]
        pose[record["seed"], half] = {"each frame": record["readings"]["shipped, each frame"]["overall"],
                                      "tracked": record["readings"]["shipped, tracked"]["overall"]}
    return pose


def _people(runs: dict, seed: int, half: str, group: str, key: str) -> int:
    return runs[seed, half][group].get(key, {}).get("people", 0)


ROWS = {
    "AP50 tracked": lambda run: run["ap50_tracked"],
    "AP50 each frame on its own": lambda run: run["ap50_each_frame"],
    "recall at the operating point": lambda run: run["recall"],
    "precision at the operating point": lambda run: run["precision"],
    "people overlapping another": lambda run: run["recall_by_group"]["overlapping another"]["recall"],
    "people apart from others": lambda run: run["recall_by_group"]["apart"]["recall"],
    "people 100 px and taller": lambda run: run["recall_by_height"][">= 100 px"]["recall"],
    "people cut by the frame's edge": lambda run: run["recall_by_edge"].get("cut by the frame", {}).get("recall"),
    "MOTA": lambda run: run["tracking"]["mota"],
    "IDF1": lambda run: run["tracking"]["idf1"],
}


def _mean(values: list[float | None]) -> str:
    present = [v for v in values if v is not None]
    return f"{np.mean(present):.3f}" if present else "–"


def _pair(values: list[float | None]) -> str:
    return " / ".join(f"{v:.3f}" if v is not None else "–" for v in values)


def camera_table(camera: str) -> list[str]:
    runs, pose = _runs(camera), _pose(camera)
    seeds = sorted({seed for seed, _ in runs})
    lines = [f"## {camera}: seeds {', '.join(map(str, seeds))}", "", "| | choosing / confirming |", "|---|---|"]
    for name, read in ROWS.items():
        cells = [_mean([read(runs[seed, half]) for seed in seeds if (seed, half) in runs]) for half in HALVES]
        lines.append(f"| {name} | {cells[0]} / {cells[1]} |")
    for kind in ("each frame", "tracked"):
        cells = [_mean([pose[seed, half][kind] for seed in seeds if (seed, half) in pose]) for half in HALVES]
        lines.append(f"| pose agreement, {kind} | {cells[0]} / {cells[1]} |")
    counts = {half: (_people(runs, seeds[0], half, "recall_by_group", "overlapping another"),
                     _people(runs, seeds[0], half, "recall_by_height", ">= 100 px"),
                     _people(runs, seeds[0], half, "recall_by_edge", "cut by the frame")) for half in HALVES}
    lines += ["", "People (choosing / confirming): overlapping another "
              f"{counts['choosing'][0]} / {counts['confirming'][0]}, 100 px and taller {counts['choosing'][1]} / "
              f"{counts['confirming'][1]}, cut by the frame {counts['choosing'][2]} / {counts['confirming'][2]}.", "",
              "| seed | AP50 tracked | each frame | pose each frame | pose tracked |", "|---|---|---|---|---|"]
    for seed in seeds:
        ap = {half: runs[seed, half] for half in HALVES}
        posed = {half: pose.get((seed, half), {}) for half in HALVES}
        lines.append(f"| {seed} | {_pair([ap[h]['ap50_tracked'] for h in HALVES])} | "
                     f"{_pair([ap[h]['ap50_each_frame'] for h in HALVES])} | "
                     f"{_pair([posed[h].get('each frame') for h in HALVES])} | "
                     f"{_pair([posed[h].get('tracked') for h in HALVES])} |")
    return lines + [""]


if __name__ == "__main__":
    text = ["# The bundles of the scenes as they ship, mean of the seeds (choosing / confirming half)", ""]
    for camera in ("pets", "tud"):
        if (RESULTS / camera).exists():
            text += camera_table(camera)
    (RESULTS / "summary.md").write_text("\n".join(text))
