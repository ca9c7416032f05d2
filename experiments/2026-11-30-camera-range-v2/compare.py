"""Does camera range v2 (heavier snow, exposure to +1.5 stops, a longer shake travelled evenly, swaying or settling)
hold against today's range? (frozen, issue 62)

Many bundles on the same changed frames: each condition of the robustness benchmark (clean, camera life, COCO-C)
changes a frame once, with the benchmark's seed, and every bundle runs it as an appliance does (scene fitness, unfit
people withheld). Per bundle and half: AP50 per condition, camera-life mPC, COCO-C mPC and rPC, COCO-C per
corruption, false people on the empty background (every person reported, and at the bundle's own operating point).

    PYTHONPATH=. python experiments/2026-11-30-camera-range-v2/compare.py --arm today/0=BUNDLE --arm v2/0=BUNDLE ... \
        --video V --gt GT --background B --frames 1:400:10 --out OUT
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from pathlib import Path

import numpy as np
from tqdm import tqdm

from benchmarks.protocol import positions_by_half
from benchmarks.robustness import (
    CAMERA_LIFE,
    CLEAN,
    COCO_C,
    BundleDetector,
    camera_life_conditions,
    clean_condition,
    coco_c_conditions,
    imagecorruptions_module,
    measure,
    performance_under_corruption,
)
from vc.deploy.frames import FrameRange, FrameSource, read_frame_image
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import evaluate
from vc.evaluation.misses import operating_point
from vc.evaluation.mot import read_mot_boxes


class StateCounting(BundleDetector):
    """A bundle that keeps its own frames' fitness states (the benchmark's measure keeps one count for all)."""

    def __init__(self, runtime: Runtime) -> None:
        super().__init__(runtime)
        self.states: Counter = Counter()

    def __call__(self, image: np.ndarray):
        found = super().__call__(image)
        self.states[self.state] += 1
        return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arm", action="append", required=True, metavar="NAME=BUNDLE")
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    parser.add_argument("--background", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, required=True)
    parser.add_argument("--severities", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--corruptions", nargs="*", default=None)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--no-camera-life", action="store_true", help="COCO-C only (another run measures the rest)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    arms = dict(arm.split("=", 1) for arm in args.arm)
    truth = read_mot_boxes(args.gt)
    frames = list(FrameSource(args.video, args.frames))
    numbers = [frame.number for frame in frames]
    halves = positions_by_half(numbers, args.frames.first, args.frames.last or numbers[-1])
    background = read_frame_image(args.background)
    corruptions = args.corruptions if args.corruptions is not None \
        else imagecorruptions_module().get_corruption_names("common")
    life = [] if args.no_camera_life else list(camera_life_conditions().values())
    conditions = [clean_condition(), *life, *coco_c_conditions(corruptions, args.severities)]
    runtimes = {name: Runtime(Path(path), threads=args.threads, unfit="suppress") for name, path in arms.items()}
    detectors = {name: StateCounting(runtime) for name, runtime in runtimes.items()}
    rows, started = [], time.perf_counter()
    with tqdm(total=len(conditions), desc="conditions") as progress:
        for condition in conditions:
            progress.set_postfix_str(condition.key)
            for detector in detectors.values():
                detector.states.clear()
            measured = measure(condition, frames, truth, background, detectors)
            rows.append((condition, measured, {name: dict(d.states) for name, d in detectors.items()}))
            progress.update()
    clean = rows[0][1]
    points = {name: operating_point(clean.images[name]).threshold for name in arms}
    report = {"arms": arms, "frames": numbers, "halves": {h: [numbers[k] for k in p] for h, p in halves.items()},
              "seconds": round(time.perf_counter() - started), "conditions": []}
    for condition, measured, states in rows:
        entry = {"key": condition.key, "family": condition.family, "states": states}
        if not condition.background_only:
            entry["ap50"] = {name: {half: round(evaluate([measured.images[name][k] for k in positions]).ap50, 4)
                                    for half, positions in halves.items()} for name in arms}
        entry["false_people"] = {name: {"reported": int(len(measured.background_scores[name])),
                                        "at_operating_point": int(np.sum(measured.background_scores[name]
                                                                         >= points[name]))} for name in arms}
        report["conditions"].append(entry)
    summary = {}
    for name in arms:
        per = {}
        for half in halves:
            clean_ap = report["conditions"][0]["ap50"][name][half]
            life = [c["ap50"][name][half] for c in report["conditions"] if c["family"] == CAMERA_LIFE and "ap50" in c]
            coco = [c["ap50"][name][half] for c in report["conditions"] if c["family"] == COCO_C]
            mpc, rpc = performance_under_corruption(coco, clean_ap) if coco else (None, None)
            per[half] = {"clean": clean_ap, "camera_life_mPC": round(float(np.mean(life)), 4),
                         "coco_mPC": None if mpc is None else round(mpc, 4),
                         "coco_rPC": None if rpc is None else round(rpc, 4),
                         "by_corruption": {c: round(float(np.mean([e["ap50"][name][half]
                                                                   for e in report["conditions"]
                                                                   if e["key"].split("/")[0] == c])), 4)
                                           for c in corruptions}}
        false = {family: round(float(np.mean([c["false_people"][name]["reported"] for c in report["conditions"]
                                              if c["family"] == family])), 3) for family in (CAMERA_LIFE, COCO_C)}
        summary[name] = {"halves": per, "false_people_per_frame_reported": false,
                         "operating_point": round(points[name], 4)}
    report["summary"] = summary
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "compare.json").write_text(json.dumps(report, indent=1))
    for name, entry in summary.items():
        for half, per in entry["halves"].items():
            print(f"{name:10s} {half:10s} clean {per['clean']:.3f} life {per['camera_life_mPC']:.3f} "
                  f"coco mPC {per['coco_mPC']} rPC {per['coco_rPC']} | "
                  + " ".join(f"{c[:6]} {v:.2f}" for c, v in per["by_corruption"].items()))
        print(f"{name:10s} false people per frame (reported): {entry['false_people_per_frame_reported']}")
    assert CLEAN == report["conditions"][0]["family"]


if __name__ == "__main__":
    main()
