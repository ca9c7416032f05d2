"""The experiment's tables: each arm (``results/tud_ARM/``: ``obstacles``, drawn as an installer draws it;
``obstacles_only``, the walkable rectangle kept; ``trimmed_only``, the trimmed ground without obstacles) against the
winter bundle of the same seed, seed by seed and half, then the means (frozen experiment, issue 57 item 2).

    python summarise.py > results/summary.md
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).parent
WINTER = HERE.parent / "2026-12-04-winter-clothing" / "results" / "tud_winter"
HALVES = ("choosing", "confirming")


def _pose() -> dict[tuple[int, str, str], dict]:
    """(seed, half, arm) -> the pose reading of ``results/pose.jsonl`` (each frame and tracked, with the swapped)."""
    readings = {}
    for line in (HERE / "results" / "pose.jsonl").read_text().splitlines():
        record = json.loads(line)
        half = HALVES[0] if record["frames"][0] == 1 else HALVES[1]
        for arm in record["bundles"]:
            readings[(record["seed"], half, arm)] = {
                way: record["readings"][f"{arm}, {way}"] for way in ("each frame", "tracked")}
    return readings


def _row(data: dict, pose: dict | None) -> list[float]:
    """AP50 tracked, each frame, overlapping recall, background false people, pose each frame, tracked, swapped."""
    row = [data["ap50_tracked"], data["ap50_each_frame"], data["recall_by_group"]["overlapping another"]["recall"],
           data["false_positives"]["background"]]
    if pose:
        each = pose["each frame"]
        row += [each["overall"], pose["tracked"]["overall"], each["swapped"] / each["people"]]
    return row


def main() -> None:
    pose = _pose()
    for folder in sorted((HERE / "results").glob("tud_*")):
        print(f"\n**{folder.name.removeprefix('tud_')}**\n")
        _table(folder, folder.name.removeprefix("tud_"), pose)


def _table(folder: Path, arm: str, pose: dict[tuple[int, str, str], dict]) -> None:
    """The arm of ``folder`` against winter, seed by seed and half, with the means."""
    columns = ("AP50 tracked", "each frame", "overlapping another", "false people in the open",
               "pose each frame", "pose tracked", "swapped each frame")
    print("| half | seed | " + " | ".join(columns) + " |")
    print("|---|---|" + "---|" * len(columns))
    for half in HALVES:
        means = {"winter": [], arm: []}
        for result in sorted(folder.glob(f"seed*_{half}.json")):
            seed = int(result.stem.split("_")[0][4:])
            rows = {"winter": _row(json.loads((WINTER / result.name).read_text()), pose.get((seed, half, "winter"))),
                    arm: _row(json.loads(result.read_text()), pose.get((seed, half, arm)))}
            for arm, row in rows.items():
                means[arm].append(row)
            print(f"| {half} | {seed} | " + " | ".join(
                f"{w:.3f} → {o:.3f}" if isinstance(w, float) else f"{w} → {o}"
                for w, o in zip(rows["winter"], rows[arm], strict=True)) + " |")
        mean = {arm: [sum(column) / len(column) for column in zip(*rows, strict=True)] for arm, rows in means.items()}
        print(f"| {half} | mean | " + " | ".join(
            f"{w:.3f} → {o:.3f}" for w, o in zip(mean["winter"], mean[arm], strict=True)) + " |")


if __name__ == "__main__":
    main()
