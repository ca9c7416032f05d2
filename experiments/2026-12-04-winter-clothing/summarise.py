"""The tables of ``results/``: each camera's arms by seed and half, with pose agreement where measured; then every
pose reading (``pose.jsonl`` and ``pose_hybrids.jsonl``) with the people read with left and right swapped; last,
winter against mixed seed by seed, the decision's table (frozen experiment, issue 57 item 2).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import json
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
HALVES = ("choosing", "confirming")


def _pose() -> dict[tuple[str, int, str, str], tuple[float, float]]:
    """(camera, seed, half, arm) -> pose agreement (each frame, tracked) from ``results/pose.jsonl``."""
    readings = {}
    path = RESULTS / "pose.jsonl"
    for line in path.read_text().splitlines() if path.exists() else []:
        record = json.loads(line)
        half = "choosing" if record["frames"][0] == 1 else "confirming"
        for arm in record["bundles"]:
            readings[(record["camera"], record["seed"], half, arm)] = (
                record["readings"][f"{arm}, each frame"]["overall"], record["readings"][f"{arm}, tracked"]["overall"])
    return readings


def main() -> None:
    pose = _pose()
    print("| camera | arm | seed | half | AP50 tracked | each frame | overlapping another | apart | recall / precision"
          " at the operating point | pose each frame / tracked |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for folder in sorted(path for path in RESULTS.glob("*_*") if path.is_dir()):  # CAMERA_ARM, not robustness/
        camera, arm = folder.name.split("_", 1)
        for result in sorted(folder.glob("seed*_*.json"), key=lambda p: (HALVES.index(p.stem.split("_")[1]), p.stem)):
            seed, half = int(result.stem.split("_")[0][4:]), result.stem.split("_")[1]
            data = json.loads(result.read_text())
            groups = data["recall_by_group"]
            overlapping = groups.get("overlapping another", {"recall": float("nan"), "people": 0})
            reading = pose.get((camera, seed, half, arm))
            print(f"| {camera} | {arm} | {seed} | {half} | {data['ap50_tracked']:.4f} | "
                  f"{data['ap50_each_frame']:.4f} | "
                  f"{overlapping['recall']:.3f} ({overlapping['people']}) | {groups['apart']['recall']:.3f} | "
                  f"{data['recall']:.3f} / {data['precision']:.3f} | "
                  + (f"{reading[0]:.3f} / {reading[1]:.3f} |" if reading else "– |"))
    pose_table()
    paired_table(pose)


def _measured() -> dict[tuple[str, str, int, str], dict]:
    """(camera, arm, seed, half) -> the measurement of ``results/CAMERA_ARM/seedS_HALF.json``."""
    found = {}
    for result in RESULTS.glob("*_*/seed*_*.json"):
        camera, arm = result.parent.name.split("_", 1)
        found[(camera, arm, int(result.stem.split("_")[0][4:]), result.stem.split("_")[1])] = json.loads(
            result.read_text())
    return found


def paired_table(pose: dict) -> None:
    """Winter minus mixed on every seed both arms have, per camera and half: the mean difference and on how many
    seeds winter is ahead, for AP50 tracked and each frame, and pose each frame and tracked."""
    measured = _measured()
    print("\n| camera | half | seeds | AP50 tracked, winter - mixed (ahead) | each frame | pose each frame "
          "| pose tracked |")
    print("|---|---|---|---|---|---|---|")
    for camera in sorted({key[0] for key in measured}):
        for half in HALVES:
            seeds = sorted(seed for (c, arm, seed, h) in measured if (c, arm, h) == (camera, "winter", half)
                           and (camera, "mixed", seed, half) in measured)
            cells = []
            for key, source in (("ap50_tracked", "box"), ("ap50_each_frame", "box"), (0, "pose"), (1, "pose")):
                if source == "box":
                    gains = [measured[(camera, "winter", s, half)][key] - measured[(camera, "mixed", s, half)][key]
                             for s in seeds]
                else:
                    read = [s for s in seeds if {(camera, s, half, arm) for arm in ("winter", "mixed")} <= pose.keys()]
                    gains = [pose[(camera, s, half, "winter")][key] - pose[(camera, s, half, "mixed")][key]
                             for s in read]
                cells.append(f"{sum(gains) / len(gains):+.3f} ({sum(g > 0 for g in gains)} of {len(gains)})"
                             if gains else "–")
            print(f"| {camera} | {half} | {', '.join(map(str, seeds))} | " + " | ".join(cells) + " |")


def pose_table() -> None:
    print("\n| camera | seed | half | bundle | pose each frame (swapped of people) | tracked (swapped) |")
    print("|---|---|---|---|---|---|")
    shown = set()  # a bundle read again beside another arm reads the same: one row each
    for name in ("pose.jsonl", "pose_hybrids.jsonl"):
        path = RESULTS / name
        for line in path.read_text().splitlines() if path.exists() else []:
            record = json.loads(line)
            half = "choosing" if record["frames"][0] == 1 else "confirming"
            for arm in record["bundles"]:
                if (record["camera"], record["seed"], half, arm) in shown:
                    continue
                shown.add((record["camera"], record["seed"], half, arm))
                each, tracked = (record["readings"][f"{arm}, {mode}"] for mode in ("each frame", "tracked"))
                print(f"| {record['camera']} | {record['seed']} | {half} | {arm} ({name}) | {each['overall']:.3f} "
                      f"({each['swapped']} of {each['people']}) | {tracked['overall']:.3f} "
                      f"({tracked['swapped']} of {tracked['people']}) |")


if __name__ == "__main__":
    main()
