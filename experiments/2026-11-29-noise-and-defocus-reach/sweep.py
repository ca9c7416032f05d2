"""How far beyond its range's noise and defocus do a bundle's networks still read people? (frozen, issue 62)

The robustness benchmark's measurement (``benchmarks.robustness.run``) with its conditions replaced by a sweep:
Gaussian noise of ``--sigmas`` codes (added to the 8-bit codes and clipped, as COCO-C's) and a defocus of ``--radii``
pixels (COCO-C's disk, alias blur 0.5), each frame on its own, the people of every frame kept (``--unfit flag``: the
networks alone, whatever the fitness says). Beside it, what the scene fitness reads for each level on the empty
background and three frames (``noise_codes``, ``sharpness``, state), so that a bound on those can be set where the
networks stop.

    PYTHONPATH=. python experiments/2026-11-29-noise-and-defocus-reach/sweep.py BUNDLE --video V --gt GT \
        --background B --frames 1:200:5 --out OUT
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np

import benchmarks.robustness as robustness
from benchmarks.robustness import COCO_C, Condition, RobustnessRequest, clean_condition, condition_seed
from vc.deploy.bundle import load_bundle
from vc.deploy.frames import FrameRange, FrameSource, read_frame_image


def gaussian(frame: np.ndarray, seed: int, sigma: float) -> np.ndarray:
    noise = np.random.default_rng(seed).normal(0.0, sigma, frame.shape)
    return np.clip(frame + noise, 0, 255).round().astype(np.uint8)


def defocus(frame: np.ndarray, seed: int, radius: int) -> np.ndarray:
    from imagecorruptions.corruptions import disk

    kernel = disk(radius=radius, alias_blur=0.5)
    image = frame.astype(np.float32)
    out = np.stack([cv2.filter2D(image[..., channel], -1, kernel) for channel in range(3)], axis=-1)
    return np.clip(out, 0, 255).round().astype(np.uint8)


def sweep_conditions(sigmas: list[float], radii: list[int]) -> list[Condition]:
    return ([clean_condition()]
            + [Condition(f"gaussian/{sigma:g}", f"Gaussian noise sigma {sigma:g} codes", COCO_C,
                         lambda frame, seed, sigma=sigma: gaussian(frame, seed, sigma), {"sigma": sigma})
               for sigma in sigmas]
            + [Condition(f"defocus/{radius}", f"defocus radius {radius} px", COCO_C,
                         lambda frame, seed, radius=radius: defocus(frame, seed, radius), {"radius": radius})
               for radius in radii])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    parser.add_argument("--background", type=Path, required=True)
    parser.add_argument("--frames", required=True)
    parser.add_argument("--sigmas", type=float, nargs="+", default=[40, 60, 80, 100, 130, 170])
    parser.add_argument("--radii", type=int, nargs="+", default=[6, 8, 10, 13, 16, 20])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    conditions = sweep_conditions(args.sigmas, args.radii)
    robustness._conditions = lambda request: conditions  # the sweep instead of the benchmark's own
    first, last, step = (int(part) for part in args.frames.split(":"))
    request = RobustnessRequest(bundle=args.bundle, video=args.video, gt=args.gt, frames=FrameRange(first, last, step),
                                background=args.background, corruptions=[], conditions=[], threads=args.threads,
                                unfit="flag", out=args.out, quiet=True)
    report = robustness.run(request)
    bundle = load_bundle(args.bundle)
    images = {"background": read_frame_image(args.background)}
    images.update({f"frame {frame.number}": frame.image
                   for frame in FrameSource(args.video, FrameRange(first, last, (last - first) // 3 or 1))})
    readings = {}
    for condition in conditions:
        readings[condition.key] = {}
        for name, image in list(images.items())[:4]:
            fitness = bundle.reference.fitness(condition.transform(image, condition_seed(condition.key, name)),
                                               bundle.fit_range).to_dict()
            readings[condition.key][name] = {key: fitness.get(key) for key in ("state", "noise_codes", "sharpness")}
    report["fitness_readings"] = readings
    report["fit_range"] = bundle.fit_range.to_dict()
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "sweep.json").write_text(json.dumps(report, indent=1))
    for condition in report["conditions"]:
        readings_line = "; ".join(f"{reading['state']} {reading['noise_codes']} {reading['sharpness']}"
                                  for reading in readings[condition["key"]].values())
        print(f"{condition['key']:>14}  AP50 {condition['ap50']['visual compiler']:.3f}  false people "
              f"{list(condition['false_people'].values())}  | {readings_line}")


if __name__ == "__main__":
    main()
