"""Scene fitness (issue 62, item 2b): what the measurements of vc.deploy.fitness read on real frames and on the
camera-life conditions, where a compiled bundle starts inventing people, and what a frame's fitness costs.

    python experiments/2026-11-28-scene-fitness/measure_fitness.py --bundle PETS_BUNDLE [--bundle-label TEXT] \
        --data ../shared/data -o experiments/2026-11-28-scene-fitness/results

1. Real frames: every frame of PETS09 S2.L1 1-400 against the scene's background (``background.png``, the image a
   compile's bundle carries), every frame of TUD-Stadtmitte against the per-pixel median of its 179 frames (the
   background a user would make of it: ``vc-scene init`` does the same). Each number's minimum, median and maximum,
   and the states.
2. Conditions, applied to every 20th PETS09 frame of 1-400 and the background, and every 9th TUD-Stadtmitte frame:
   black, uniform grey, noise, exposure in stops through the sRGB curve (-3 to +2) and as the issue scaled codes
   (x0.5, x0.35), white balance (codes, R and B gains), IR monochrome (code luma in all three channels), Gaussian
   blur (sigma 0.5-4 px, and sigma 2 with noise added after it, as a sensor adds it behind a dirty lens), shifts
   (1-16 px across, 12 px down and diagonally; reflected at the border), the left half of the view blocked (a parked
   truck) and the other camera's frame resized (another view). The states and the numbers.
3. Where the bundle starts inventing people (``--bundle``: a PETS09 bundle; each frame on its own): the same
   conditions on the empty background (truth 0) and on the 20 dev frames, people reported and people matching no
   ground-truth box at IoU 0.5.
4. Cost: ``SceneReference.fitness`` per frame on PETS09 and TUD-Stadtmitte (median of every frame, after one warm
   frame), and its parts.

Writes ``scene_fitness.json`` and ``scene_fitness.md`` under ``-o``.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from pathlib import Path

import cv2
import numpy as np

from vc.calibration.response import Response
from vc.deploy import fitness as fit
from vc.deploy.boxes import box_iou
from vc.deploy.runtime import Runtime
from vc.evaluation.mot import read_mot_boxes

SRGB = Response("srgb")
DECODE = SRGB.decode(np.arange(256, dtype=np.uint8)).astype(np.float32)
NUMBERS = ("spread", "coherence", "exposure_stops", "matching", "sharpness", "shift_distance_px", "shift_peak",
           "colour_left", "colour_cast_stops")


def rgb(path: Path) -> np.ndarray:
    return np.ascontiguousarray(cv2.imread(str(path))[:, :, ::-1])


def pets_frames(video: Path, last: int = 400):
    capture = cv2.VideoCapture(str(video))
    for number in range(1, last + 1):
        ok, bgr = capture.read()
        if not ok:
            return
        yield number, np.ascontiguousarray(bgr[:, :, ::-1])


def exposed(image: np.ndarray, stops: float) -> np.ndarray:
    return SRGB.encode(SRGB.decode(image) * np.float32(2.0 ** stops))


def gains(image: np.ndarray, red: float, blue: float) -> np.ndarray:
    return np.clip(image * np.array([red, 1.0, blue], np.float32), 0, 255).astype(np.uint8)


def shifted(image: np.ndarray, dx: float, dy: float) -> np.ndarray:
    matrix = np.float32([[1, 0, dx], [0, 1, dy]])
    return cv2.warpAffine(image, matrix, (image.shape[1], image.shape[0]), borderMode=cv2.BORDER_REFLECT)


def conditions() -> dict:
    """name -> (expected state, image -> image)."""
    rng = np.random.default_rng(0)
    result = {"as recorded": ("ok", lambda image: image),
              "black": ("covered", np.zeros_like),
              "uniform grey": ("covered", lambda image: np.full_like(image, 128)),
              "noise": ("covered", lambda image: rng.integers(0, 256, image.shape, dtype=np.uint8))}
    for stops in (-3, -2, -1.5, -1, -0.5, 0.5, 1, 1.5, 2):
        expected = "dark" if stops < -1 else "overexposed" if stops > 1 else None
        result[f"{stops:+g} stops"] = (expected, lambda image, s=stops: exposed(image, s))
    for factor in (0.5, 0.35):
        result[f"codes x{factor}"] = ("dark", lambda image, f=factor: (image * f).astype(np.uint8))
    result["codes x2 (clipped)"] = ("overexposed", lambda image: np.clip(image * 2.0, 0, 255).astype(np.uint8))
    for name, red, blue in (("warm", 1.25, 0.8), ("cool", 0.8, 1.25), ("slightly warm", 1.1, 0.9),
                            ("barely warm", 1.05, 0.95)):
        expected = "changed" if name in ("warm", "cool") else None
        result[f"white balance {name} (R x{red}, B x{blue})"] = (expected,
                                                                  lambda image, r=red, b=blue: gains(image, r, b))
    result["IR monochrome"] = ("changed", lambda image: np.repeat(
        (image @ np.array([0.299, 0.587, 0.114], np.float32)).round().astype(np.uint8)[..., None], 3, axis=2))
    for sigma in (0.5, 1, 2, 4):
        expected = "blurred" if sigma >= 2 else None
        result[f"blur sigma {sigma:g}"] = (expected, lambda image, s=sigma: cv2.GaussianBlur(image, (0, 0), s))
    result["blur sigma 2 + noise sigma 2"] = ("blurred", lambda image: np.clip(
        cv2.GaussianBlur(image, (0, 0), 2) + rng.normal(0, 2, image.shape), 0, 255).astype(np.uint8))
    for pixels in (1, 2, 3, 4, 6, 8, 12, 16):
        expected = "moved" if pixels >= 6 else None
        result[f"shift {pixels} px across"] = (expected, lambda image, d=pixels: shifted(image, d, 0))
    result["shift 12 px down"] = ("moved", lambda image: shifted(image, 0, 12))
    result["shift 8 px diagonally"] = ("moved", lambda image: shifted(image, 8, 8))
    result["left half blocked (a parked truck)"] = ("changed", blocked)
    result["another camera's view"] = ("changed", None)  # filled per scene: the other camera's frame, resized
    return result


def blocked(image: np.ndarray) -> np.ndarray:
    """The left half of the view behind something flat and grey-blue with a darker band: a parked truck."""
    out = image.copy()
    out[:, :image.shape[1] // 2] = (96, 104, 118)
    out[image.shape[0] // 3:image.shape[0] // 3 + 12, :image.shape[1] // 2] = (40, 44, 52)
    return out


def numbers(fitness: fit.FrameFitness) -> dict:
    values = {name: getattr(fitness, name) for name in NUMBERS if name != "shift_distance_px"}
    values["shift_distance_px"] = float(np.hypot(*fitness.shift_px))
    return values


def ranges(rows: list[dict]) -> dict:
    result = {}
    for name in NUMBERS:
        values = [row[name] for row in rows if row[name] is not None]
        result[name] = ([round(float(np.min(values)), 3), round(float(np.median(values)), 3),
                         round(float(np.max(values)), 3)] if values else None)
    return result


def measure_set(reference: fit.SceneReference, frames: list[np.ndarray]) -> dict:
    fitnesses = [reference.fitness(frame) for frame in frames]
    return {"frames": len(frames), "states": dict(Counter(f.state for f in fitnesses)),
            "numbers": ranges([numbers(f) for f in fitnesses])}


def unmatched(people_boxes: np.ndarray, truth: np.ndarray) -> int:
    """People matching no ground-truth box at IoU 0.5 (greedy, best first)."""
    if not len(people_boxes):
        return 0
    if not len(truth):
        return len(people_boxes)
    iou = box_iou(people_boxes, truth)
    free, false = np.ones(len(truth), bool), 0
    for row in iou:
        candidates = np.where(free, row, 0.0)
        if candidates.max() >= 0.5:
            free[int(np.argmax(candidates))] = False
        else:
            false += 1
    return false


def timings(reference: fit.SceneReference, frames: list[np.ndarray]) -> dict:
    reference.fitness(frames[0])
    parts = {"fitness": lambda f: reference.fitness(f), "cell_means": lambda f: fit.cell_means(f, reference.cell_px),
             "fine_energy": lambda f: fit.fine_energy(f, reference.cell_px)}
    result = {}
    for name, call in parts.items():
        seconds = []
        for frame in frames:
            start = time.perf_counter()
            call(frame)
            seconds.append(time.perf_counter() - start)
        result[name] = {"median_ms": round(float(np.median(seconds)) * 1e3, 3),
                        "p90_ms": round(float(np.percentile(seconds, 90)) * 1e3, 3)}
    return result


def markdown(results: dict) -> str:
    lines = ["# Scene fitness: measurements", "", "Written by `measure_fitness.py` (see its docstring and the "
             "folder's README). Numbers: minimum / median / maximum over the frames.", ""]
    short = {"spread": "spread", "coherence": "coherence", "exposure_stops": "stops", "matching": "matching",
             "sharpness": "sharpness", "shift_distance_px": "shift px", "shift_peak": "peak",
             "colour_left": "colour left", "colour_cast_stops": "cast"}

    def table(title: str, sets: dict) -> None:
        lines.extend([f"## {title}", "", "| frames | expected | states | " + " | ".join(short.values()) + " |",
                      "|---|---|---|" + "---|" * len(short)])
        for name, entry in sets.items():
            cells = []
            for key in short:
                value = entry["numbers"][key]
                cells.append("–" if value is None else "/".join(f"{v:.3g}" for v in value))
            states = ", ".join(f"{count} {state}" for state, count in sorted(entry["states"].items()))
            lines.append(f"| {name} | {entry.get('expected') or '–'} | {states} | " + " | ".join(cells) + " |")
        lines.append("")

    table("Real frames", results["real"])
    for scene in ("pets09", "tud_stadtmitte"):
        table(f"Conditions, {scene}", results["conditions"][scene])
    if "bundle" in results:
        lines.extend(["## People the bundle reports under each condition", "",
                      f"Bundle: `{results['bundle']['path']}`, each frame on its own. Background: the empty "
                      "background (truth 0). Dev frames: mean people per frame reported and matching no "
                      "ground-truth box at IoU 0.5 (truth: "
                      f"{results['bundle']['dev_truth_per_frame']:.2f} people per frame).", "",
                      "| condition | background: people | dev frames: people | dev frames: false people | "
                      "PETS09 states |", "|---|---|---|---|---|"])
        states = results["conditions"]["pets09"]
        for name, entry in results["bundle"]["conditions"].items():
            state = ", ".join(f"{c} {s}" for s, c in sorted(states[name]["states"].items()))
            lines.append(f"| {name} | {entry['background_people']} | {entry['dev_people_per_frame']:.2f} | "
                         f"{entry['dev_false_per_frame']:.2f} | {state} |")
        lines.append("")
    lines.extend(["## Cost per frame", "", "| camera | fitness | cell means | fine energy |", "|---|---|---|---|"])
    for scene, entry in results["timings"].items():
        lines.append(f"| {scene} | {entry['fitness']['median_ms']:.2f} ms (p90 {entry['fitness']['p90_ms']:.2f}) | "
                     f"{entry['cell_means']['median_ms']:.2f} ms | {entry['fine_energy']['median_ms']:.2f} ms |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, required=True, help="the folder holding pets09_s2l1 and tud_stadtmitte")
    parser.add_argument("--bundle", type=Path, help="a PETS09 bundle: where it starts inventing people")
    parser.add_argument("--bundle-label", default="a PETS09 bundle", help="what the results call it (no paths)")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()
    pets = args.data / "pets09_s2l1"
    background = rgb(pets / "background.png")
    pets_reference = fit.SceneReference.of_background(background, DECODE)
    pets_all = dict(pets_frames(pets / "vtest.avi"))
    tud_frames = [rgb(path) for path in sorted((args.data / "tud_stadtmitte" / "frames").glob("*.png"))]
    tud_background = np.median(np.stack(tud_frames), axis=0).round().astype(np.uint8)
    tud_reference = fit.SceneReference.of_background(tud_background, DECODE)

    results: dict = {"references": {
        "pets09": {"image": "pets09_s2l1/background.png", "cell_px": pets_reference.cell_px,
                   "cells": list(pets_reference.cells.shape[:2]), "bytes": len(pets_reference.to_bytes())},
        "tud_stadtmitte": {"image": "median of the 179 frames", "cell_px": tud_reference.cell_px,
                           "cells": list(tud_reference.cells.shape[:2]), "bytes": len(tud_reference.to_bytes())}},
        "thresholds": {name: getattr(fit, name) for name in (
            "COVERED_SPREAD", "COVERED_COHERENCE", "MATCH_STOPS", "DARK_STOPS", "OVEREXPOSED_STOPS",
            "BLURRED_SHARPNESS", "MOVED_PX", "MOVED_PEAK", "CHANGED_AGREEMENT", "COLOUR_LEFT", "COLOUR_CAST_STOPS")}}
    results["real"] = {"PETS09 1-400": measure_set(pets_reference, list(pets_all.values())),
                       "PETS09 background itself": measure_set(pets_reference, [background]),
                       "TUD-Stadtmitte 1-179": measure_set(tud_reference, tud_frames),
                       "TUD-Stadtmitte median itself": measure_set(tud_reference, [tud_background])}
    samples = {"pets09": (pets_reference, [background] + [pets_all[n] for n in range(1, 401, 20)]),
               "tud_stadtmitte": (tud_reference, tud_frames[::9])}
    others = {"pets09": samples["tud_stadtmitte"][1], "tud_stadtmitte": samples["pets09"][1]}
    results["conditions"] = {}
    for scene, (reference, frames) in samples.items():
        results["conditions"][scene] = {}
        for name, (expected, change) in conditions().items():
            if change is None:  # another camera's view: the other scene's frames at this one's size
                other = iter(others[scene] * 2)
                size = (frames[0].shape[1], frames[0].shape[0])
                change = lambda image, o=other, s=size: cv2.resize(next(o), s, interpolation=cv2.INTER_AREA)  # noqa: E731
            entry = measure_set(reference, [change(frame) for frame in frames])
            results["conditions"][scene][name] = {"expected": expected, **entry}
            print(f"{scene:15s} {name:40s} {entry['states']}")
    if args.bundle:
        truth = read_mot_boxes(pets / "gt_dev_frames_0001-0400.txt")
        dev = list(range(1, 401, 20))
        bundle: dict = {"path": args.bundle_label, "dev_frames": dev,
                        "dev_truth_per_frame": float(np.mean([len(truth.get(n, [])) for n in dev])), "conditions": {}}
        with Runtime(args.bundle, unfit="flag") as runtime:
            for name, (_, change) in conditions().items():
                if change is None:
                    tud_for_pets = iter(samples["tud_stadtmitte"][1] * 3)
                    change = lambda image, o=tud_for_pets: cv2.resize(next(o), (768, 576),  # noqa: E731
                                                                      interpolation=cv2.INTER_AREA)
                reported, false = [], []
                for number in dev:
                    people = runtime(change(pets_all[number]))
                    boxes = np.array([person.box for person in people]).reshape(-1, 4)
                    reported.append(len(people))
                    false.append(unmatched(boxes, truth.get(number, np.zeros((0, 4)))))
                bundle["conditions"][name] = {"background_people": len(runtime(change(background))),
                                              "dev_people_per_frame": float(np.mean(reported)),
                                              "dev_false_per_frame": float(np.mean(false))}
                print(f"bundle {name:40s} {bundle['conditions'][name]}")
        results["bundle"] = bundle
    results["timings"] = {"pets09 (768x576)": timings(pets_reference, list(pets_all.values())),
                          "tud_stadtmitte (640x480)": timings(tud_reference, tud_frames)}
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "scene_fitness.json").write_text(json.dumps(results, indent=1) + "\n")
    (args.output / "scene_fitness.md").write_text(markdown(results))
    print(markdown(results))


if __name__ == "__main__":
    main()
