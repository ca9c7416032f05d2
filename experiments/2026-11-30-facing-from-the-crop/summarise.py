"""The facing model's arm against its control, per camera, half and seed, from vc-eval's metrics (frozen).

    PYTHONPATH=. python experiments/2026-11-30-facing-from-the-crop/summarise.py EVAL_ROOT
EVAL_ROOT/{control,facing,facing_walk,facing_networks_trusted}/{pets,tud}{0,1,2}/{1,201,91}/metrics.json, as
run.sh writes them.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
HALVES = {"pets": {"choosing": "1", "confirming": "201"}, "tud": {"choosing": "1", "confirming": "91"}}
TRACKED, EACH_FRAME = "visual compiler", "visual compiler, each frame on its own"


def reading(path: Path) -> dict:
    metrics = json.loads(path.read_text())
    agreement = metrics["pose_agreement"]["agreement"]
    return {"pose_tracked": agreement[TRACKED]["overall"], "pose_each_frame": agreement[EACH_FRAME]["overall"],
            "swapped_each_frame": agreement[EACH_FRAME]["people_left_right_swapped"] / agreement[EACH_FRAME]["people"],
            "ap50_tracked": metrics["detectors"][TRACKED]["ap50"],
            "ap50_each_frame": metrics["detectors"][EACH_FRAME]["ap50"],
            "ms_each_frame": metrics["detectors"][EACH_FRAME]["ms_per_frame"]["median"]}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("root", type=Path)
    root = parser.parse_args().root
    arms = ("control", "facing", "facing_walk", "facing_networks_trusted")
    table, rows = {}, []
    for camera, halves in HALVES.items():
        for half, first in halves.items():
            for seed in range(3):
                entry = {arm: reading(root / arm / f"{camera}{seed}" / first / "metrics.json") for arm in arms}
                table[f"{camera}/{half}/{seed}"] = entry
                control, facing, walk, trusted = (entry[arm] for arm in arms)
                rows.append(f"| {camera} | {half} | {seed} | {control['pose_each_frame']:.3f} → "
                            f"**{facing['pose_each_frame']:.3f}** | {control['swapped_each_frame']:.2f} → "
                            f"{facing['swapped_each_frame']:.2f} | {control['pose_tracked']:.3f} | "
                            f"{facing['pose_tracked']:.3f} | {walk['pose_tracked']:.3f} | "
                            f"**{trusted['pose_tracked']:.3f}** | "
                            f"{control['ap50_tracked']:.3f} → {facing['ap50_tracked']:.3f} |")
            means = {arm: {key: sum(table[f"{camera}/{half}/{seed}"][arm][key] for seed in range(3)) / 3
                           for key in ("pose_each_frame", "pose_tracked")} for arm in arms}
            rows.append(f"| {camera} | {half} | mean | {means['control']['pose_each_frame']:.3f} → "
                        f"**{means['facing']['pose_each_frame']:.3f}** | | {means['control']['pose_tracked']:.3f} | "
                        f"{means['facing']['pose_tracked']:.3f} | {means['facing_walk']['pose_tracked']:.3f} | "
                        f"**{means['facing_networks_trusted']['pose_tracked']:.3f}** | |")
    header = ["| camera | half | seed | pose each frame: control → facing model | people read with left and right "
              "exchanged, each frame | pose tracked: control | facing model, confident model over an unclear walk "
              "| facing model, the walk decides wherever there is one | facing model, the networks' confidence weighed "
              "against an unclear walk | AP50 tracked |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    text = "\n".join(header + rows) + "\n"
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results/facing_arm.md").write_text(text)
    (HERE / "results/facing_arm.json").write_text(json.dumps(table, indent=1) + "\n")
    print(text)


if __name__ == "__main__":
    main()
