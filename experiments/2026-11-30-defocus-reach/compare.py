"""Do the networks lose to defocus on the export's test frames as they do on the camera's real frames? (frozen,
issue 62, docs/decisions/0023-defocus-reach.md)

A reach measured at export could only use the frames the export has: the self-test's test frames (held-out renders
pasted into the background). This measures whether they lose to defocus as the camera's real frames do. One compiled
bundle, defocused at radii 6, 8 and 10 px two ways: the camera range's focus drift (a disc in linear light through
the scene's response) and COCO-C's disk (on the 8-bit codes, what the robustness benchmark applies). AP50 with every
frame's people kept (the networks alone) and people on the empty background (at the operating point, every one
reported), on real frames with ground truth (the robustness benchmark's measurement) and on 50 test frames, with the
least sharpness the scene fitness reads on those and the background.

    PYTHONPATH=. python experiments/2026-11-30-defocus-reach/compare.py COMPILE_OUT --video V --gt GT \
        --background B --frames 1:200:5 --response srgb --out OUT
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

import benchmarks.robustness as robustness
from benchmarks.robustness import COCO_C, Condition, RobustnessRequest, clean_condition
from vc.calibration.noise import NoiseModel
from vc.calibration.response import Response
from vc.deploy.bundle import load_bundle
from vc.deploy.frames import FrameRange
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.selftest import composite_frame
from vc.io import read_image
from vc.model.camera_range import CameraLife, CameraRange
from vc.model.camera_range import Condition as Drift
from vc.render.dataset import open_region, read_manifest

RADII = (6, 8, 10)
TEST_FRAMES = 50


def coco_disk(frame: np.ndarray, radius: int) -> np.ndarray:
    from imagecorruptions.corruptions import disk

    kernel = disk(radius=radius, alias_blur=0.5)
    image = frame.astype(np.float32)
    out = np.stack([cv2.filter2D(image[..., channel], -1, kernel) for channel in range(3)], axis=-1)
    return np.clip(out, 0, 255).round().astype(np.uint8)


def conditions(response: str) -> list[Condition]:
    life = CameraLife(CameraRange(), Response(response), NoiseModel(0.0, 0.0), 1.0)

    def linear(frame: np.ndarray, radius: int) -> np.ndarray:
        return life.render(frame, Drift(defocus_px=float(radius)), np.random.default_rng(0))

    return ([clean_condition()]
            + [Condition(f"coco/{radius}", f"COCO-C disk radius {radius}", COCO_C,
                         lambda frame, seed, radius=radius: coco_disk(frame, radius), {}) for radius in RADII]
            + [Condition(f"linear/{radius}", f"linear-light disc radius {radius}", COCO_C,
                         lambda frame, seed, radius=radius: linear(frame, radius), {}) for radius in RADII])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("compiled", type=Path, help="a vc-compile output folder (bundle/, renders/)")
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    parser.add_argument("--background", type=Path, required=True)
    parser.add_argument("--frames", required=True)
    parser.add_argument("--response", default="srgb")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    chosen = conditions(args.response)
    robustness._conditions = lambda request: chosen  # these instead of the benchmark's own
    first, last, step = (int(part) for part in args.frames.split(":"))
    report = robustness.run(RobustnessRequest(
        bundle=args.compiled / "bundle", video=args.video, gt=args.gt, frames=FrameRange(first, last, step),
        background=args.background, corruptions=[], conditions=[], threads=2, unfit="flag", out=args.out / "real",
        quiet=True))
    rows = {condition["key"]: {"real_ap50": condition["ap50"]["visual compiler"],
                               "real_false_people": list(condition["false_people"].values())}
            for condition in report["conditions"]}
    bundle = load_bundle(args.compiled / "bundle")
    renders = args.compiled / "renders"
    regions = [open_region(renders, name) for name in read_manifest(renders)["regions"]]
    background = read_image(args.background)
    tests = [composite_frame(background, regions, index) for index in range(TEST_FRAMES)]
    with Runtime(replace(bundle, reference=None), unfit="flag") as runtime:
        for condition in chosen:
            results, sharpness = [], []
            for index, test in enumerate(tests):
                image = condition.transform(test.image, index)
                people = runtime(image)
                results.append(ImageResult(test.truth_boxes, np.array([p.box for p in people]).reshape(-1, 4),
                                           np.array([p.score for p in people]), truth_ignore=test.truth_ignore))
                sharpness.append(bundle.reference.fitness(image).sharpness)
            empty = condition.transform(background, 0)
            sharpness.append(bundle.reference.fitness(empty).sharpness)
            rows[condition.key].update({"renders_ap50": evaluate(results).ap50,
                                        "renders_false_people": len(runtime(empty)),
                                        "least_sharpness": min(sharpness)})
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "compare.json").write_text(json.dumps(rows, indent=1) + "\n")
    clean = rows["clean"]
    lines = ["| blur | real AP50 (of clean) | people on the background | test frames AP50 (of clean) | people on the "
             "background | least sharpness |", "|---|---|---|---|---|---|"]
    for key, row in rows.items():
        lines.append(f"| {key} | {row['real_ap50']:.3f} ({row['real_ap50'] / clean['real_ap50']:.2f}) | "
                     f"{row['real_false_people']} | {row['renders_ap50']:.3f} "
                     f"({row['renders_ap50'] / clean['renders_ap50']:.2f}) | {row['renders_false_people']} | "
                     f"{row['least_sharpness']:.4f} |")
    (args.out / "compare.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
