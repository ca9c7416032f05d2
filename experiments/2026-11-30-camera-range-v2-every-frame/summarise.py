"""Camera range v2 against today's, by the confirming halves' rule (frozen, issue 62, decision record 0025): clean
AP50 on every frame of each half (vc-eval's metrics.json, tracked and each frame on its own), and, from
compare.py's runs or results, under camera life and COCO-C on the benchmark's frames, merged by arm.

    PYTHONPATH=. python experiments/2026-11-30-camera-range-v2-every-frame/summarise.py \
        --clean ARM/SEED/DATASET/HALF=EVAL_DIR ... --compare RESULTS_OR_RUN ... --out results/every_frame.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from benchmarks.robustness import CAMERA_LIFE, COCO_C, performance_under_corruption

TRACKED, EACH_FRAME = "visual compiler", "visual compiler, each frame on its own"


def clean_table(specs: list[str]) -> dict:
    """{arm: {dataset: {half: {"tracked": [per seed], "each_frame": [per seed]}}}} from vc-eval's metrics.json."""
    table: dict = {}
    for spec in sorted(specs):
        key, folder = spec.split("=", 1)
        arm, _seed, dataset, half = key.split("/")
        detectors = json.loads((Path(folder) / "metrics.json").read_text())["detectors"]
        entry = table.setdefault(arm, {}).setdefault(dataset, {}).setdefault(half, {"tracked": [], "each_frame": []})
        entry["tracked"].append(detectors[TRACKED]["ap50"])
        entry["each_frame"].append(detectors[EACH_FRAME]["ap50"])
    return table


def merged_conditions(sources: list[Path]) -> list[dict]:
    """Every condition once, holding every arm's AP50, states and false people from any of ``sources`` (a
    compare.py run folder or a summarise.py result holding ``conditions``)."""
    merged: dict[str, dict] = {}
    for source in sources:
        report = json.loads(((source / "compare.json") if source.is_dir() else source).read_text())
        for condition in report["conditions"]:
            into = merged.setdefault(condition["key"], {"key": condition["key"], "family": condition["family"]})
            for field in ("ap50", "states", "false_people"):
                if field in condition:
                    into.setdefault(field, {}).update(condition[field])
    return list(merged.values())


def robustness_table(conditions: list[dict]) -> dict:
    """Per arm and half: clean AP50, camera-life mPC, COCO-C mPC and rPC, snow, frost and brightness; per arm the
    people reported a frame on the corrupted empty background."""
    clean = next(c for c in conditions if c["family"] == "clean")
    summary = {}
    for arm in clean["ap50"]:
        per = {}
        for half in clean["ap50"][arm]:
            life = [c["ap50"][arm][half] for c in conditions if c["family"] == CAMERA_LIFE and "ap50" in c]
            coco = [c["ap50"][arm][half] for c in conditions if c["family"] == COCO_C]
            mpc, rpc = performance_under_corruption(coco, clean["ap50"][arm][half])
            per[half] = {"clean": clean["ap50"][arm][half], "camera_life_mPC": round(float(np.mean(life)), 4),
                         "coco_mPC": round(mpc, 4), "coco_rPC": round(rpc, 4), "coco_conditions": len(coco)}
            for name in ("snow", "frost", "brightness"):
                per[half][name] = round(float(np.mean([c["ap50"][arm][half] for c in conditions
                                                       if c["key"].split("/")[0] == name])), 4)
        false = float(np.mean([c["false_people"][arm]["reported"] for c in conditions if c["family"] == COCO_C]))
        summary[arm] = {"halves": per, "coco_false_people_per_frame_reported": round(false, 3)}
    return summary


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--clean", nargs="+", default=[], metavar="ARM/SEED/DATASET/HALF=EVAL_DIR")
    parser.add_argument("--compare", type=Path, nargs="+", default=[])
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    clean = clean_table(args.clean)
    robustness = robustness_table(merged_conditions(args.compare)) if args.compare else {}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"clean_every_frame": clean, "robustness": robustness}, indent=1))
    for arm, datasets in clean.items():
        for dataset, halves in datasets.items():
            for half, entry in halves.items():
                print(f"{arm:6s} {dataset:5s} {half:10s} tracked {' '.join(f'{v:.3f}' for v in entry['tracked'])} "
                      f"(mean {np.mean(entry['tracked']):.3f})  each frame "
                      f"{' '.join(f'{v:.3f}' for v in entry['each_frame'])} (mean {np.mean(entry['each_frame']):.3f})")
    for arm, entry in robustness.items():
        for half, per in entry["halves"].items():
            print(f"{arm:9s} {half:10s} " + " ".join(f"{name} {value:.3f}" for name, value in per.items()
                                                      if name != "coco_conditions"))
        print(f"{arm:9s} COCO-C false people a frame (every one reported): "
              f"{entry['coco_false_people_per_frame_reported']}")


if __name__ == "__main__":
    main()
