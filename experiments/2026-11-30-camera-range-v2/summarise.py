"""The A/B's table from compare.py's runs over parts of the conditions (frozen, issue 62): per arm and half, clean
AP50, camera-life mPC, COCO-C mPC and rPC over all 15 corruptions, per corruption, false people on the background.

    PYTHONPATH=. python experiments/2026-11-30-camera-range-v2/summarise.py RUN_DIR ... --out results/ab.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from benchmarks.robustness import CAMERA_LIFE, COCO_C, performance_under_corruption


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    reports = [json.loads((run / "compare.json").read_text()) for run in args.runs]
    conditions, seen = [], set()
    for report in reports:
        for condition in report["conditions"]:
            if condition["key"] not in seen:
                seen.add(condition["key"])
                conditions.append(condition)
    arms, halves = list(reports[0]["arms"]), list(reports[0]["halves"])
    clean = next(c for c in conditions if c["family"] == "clean")
    corruptions = sorted({c["key"].split("/")[0] for c in conditions if c["family"] == COCO_C})
    summary = {}
    for arm in arms:
        per = {}
        for half in halves:
            life = [c["ap50"][arm][half] for c in conditions if c["family"] == CAMERA_LIFE and "ap50" in c]
            coco = [c["ap50"][arm][half] for c in conditions if c["family"] == COCO_C]
            mpc, rpc = performance_under_corruption(coco, clean["ap50"][arm][half])
            per[half] = {"clean": clean["ap50"][arm][half], "camera_life_mPC": round(float(np.mean(life)), 4),
                         "coco_mPC": round(mpc, 4), "coco_rPC": round(rpc, 4), "coco_conditions": len(coco),
                         "by_corruption": {name: round(float(np.mean([c["ap50"][arm][half] for c in conditions
                                                                      if c["key"].split("/")[0] == name])), 4)
                                           for name in corruptions}}
        false = {family: round(float(np.mean([c["false_people"][arm]["reported"] for c in conditions
                                              if c["family"] == family])), 3) for family in (CAMERA_LIFE, COCO_C)}
        summary[arm] = {"halves": per, "false_people_per_frame_reported": false}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"runs": [str(run) for run in args.runs], "summary": summary,
                                    "conditions": conditions}, indent=1))
    for arm, entry in summary.items():
        for half, per in entry["halves"].items():
            print(f"{arm:8s} {half:10s} clean {per['clean']:.3f} life {per['camera_life_mPC']:.3f} "
                  f"mPC {per['coco_mPC']:.3f} rPC {per['coco_rPC']:.3f} | "
                  + " ".join(f"{name[:5]} {value:.2f}" for name, value in per["by_corruption"].items()))
        print(f"{arm:8s} false people per frame (every one reported): {entry['false_people_per_frame_reported']}")


if __name__ == "__main__":
    main()
