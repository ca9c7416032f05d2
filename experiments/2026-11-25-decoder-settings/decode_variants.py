"""What the decoder's settings buy on real frames, without retraining: one bundle's heat maps on the frames are
computed once, then decoded under each variant of its regions' ``DecodeConfig``; real AP50 and the miss analysis
(:mod:`vc.evaluation.misses`) of each variant.

    python experiments/2026-11-25-decoder-settings/decode_variants.py BUNDLE --video V --gt GT.txt [--frames 1:400:5]
        [--variant NAME FIELD=VALUE [FIELD=VALUE ...]]... [--external POSE_MODEL.onnx]
        --out experiments/2026-11-25-decoder-settings/results

Without ``--variant`` the variants of :data:`VARIANTS` run. With ``--external`` (a YOLO-pose ONNX model, run
once per frame) each variant also reports its pose agreement with that model (:mod:`vc.evaluation.agreement`).
Writes ``decode_variants.json`` and a table ``decode_variants.md`` to ``--out``. The bundle's own settings are always
the first row.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
from tqdm import tqdm

from vc.deploy.decode import DecodeConfig
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import SEAM_FOOT_TOLERANCE, Runtime, without_seam_duplicates
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.annotated_area import AnnotatedArea
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.misses import FALSE_POSITIVE_KINDS, analyse_misses, region_lookup
from vc.evaluation.mot import read_mot_boxes
from vc.io import write_json

#: Variants measured by default: name -> DecodeConfig fields changed from the bundle's.
VARIANTS: dict[str, dict] = {
    "centre separation 0.10": {"min_centre_separation": 0.10},
    "centre separation 0.25": {"min_centre_separation": 0.25},
    "reach sideways 0.15": {"reach_sideways": 0.15},
    "reach sideways 0.25": {"reach_sideways": 0.25},
    "reach sideways 0.3": {"reach_sideways": 0.3},
    "keypoints >= 0.4 shape the box": {"keypoint_threshold": 0.4},
    "mask >= 0.7": {"mask_threshold": 0.7},
    "height from the camera only (before)": {"height_from_keypoints": False},
    "height from head and ankles within 1.3x": {"keypoint_height_range": 1.3},
    "height from head and ankles within 2x": {"keypoint_height_range": 2.0},
    # Step 1b and 2b (results/decode_votes.md): the defaults before, and the next step down.
    "votes of 0.3 of a person (before)": {"vote_support": 0.3},
    "votes of 0.1 of a person": {"vote_support": 0.1},
    "keypoint peaks shared (before)": {"exclusive_keypoints": False},
    # Step 1b's reach apart from the peaks' separation (results/vote_reach_pets09.md).
    "votes reach 0.12": {"vote_separation": 0.12},
    "votes reach 0.10": {"vote_separation": 0.10},
}


def _field_value(name: str, text: str):
    types = {field.name: field.type for field in fields(DecodeConfig)}
    if name not in types:
        raise SystemExit(f"--variant: DecodeConfig has no field {name!r} (it has {', '.join(types)})")
    if types[name] in (bool, "bool"):
        if text.lower() not in ("true", "false"):
            raise SystemExit(f"--variant: {name} is true or false, not {text!r}")
        return text.lower() == "true"
    return int(text) if types[name] in (int, "int") else float(text)


def parse_variants(values: list[list[str]] | None) -> dict[str, dict]:
    if not values:
        return VARIANTS
    variants = {}
    for name, *settings in values:
        variants[name] = {key: _field_value(key, value) for key, value in (s.split("=", 1) for s in settings)}
    return variants


def heatmaps_of(runtime: Runtime, source: FrameSource) -> tuple[list[int], list[list[np.ndarray]]]:
    """Frame numbers, and per frame each region's heat maps."""
    numbers, maps = [], []
    for frame in tqdm(source, total=len(source), desc="heat maps", unit="frame"):
        numbers.append(frame.number)
        maps.append([runner.heatmaps(frame.image) for runner in runtime.runners])
    return numbers, maps


def reference_poses(model_path: Path, source: FrameSource, truth: dict[int, np.ndarray]) -> list[ImageResult]:
    """A reference pose model's people on every frame (for the agreement of each variant's keypoints)."""
    model = YoloPoseOnnx(model_path)
    images = []
    for frame in tqdm(source, total=len(source), desc=model_path.name, unit="frame"):
        detections = model(frame.image)
        images.append(ImageResult(truth.get(frame.number, np.zeros((0, 4))),
                                  np.asarray(detections.boxes).reshape(-1, 4),
                                  np.asarray(detections.scores, np.float64).ravel(), keypoints=detections.keypoints))
    return images


def measure(runtime: Runtime, numbers: list[int], maps: list[list[np.ndarray]], truth: dict[int, np.ndarray],
            changes: dict, reference: list[ImageResult] | None = None,
            seam_tolerance: float = SEAM_FOOT_TOLERANCE) -> dict:
    """AP50 and the miss analysis's headline numbers with ``changes`` applied to every region's DecodeConfig (and
    people kept across a seam within ``seam_tolerance``), and the keypoints' agreement with ``reference`` when
    given."""
    images = []
    for number, per_region in zip(numbers, maps, strict=True):
        # as the runtime reports a frame: every region's people, strongest first, one of each seam duplicate
        people = without_seam_duplicates(sorted(
            (person for runner, heatmaps in zip(runtime.runners, per_region, strict=True)
             for person in runner.people_in(heatmaps, replace(runner.entry.decode, **changes), seam_tolerance)),
            key=lambda person: -person.score))
        images.append(ImageResult(truth.get(number, np.zeros((0, 4))), np.array([p.box for p in people]).reshape(-1, 4),
                                  np.array([p.score for p in people]),
                                  keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3)))
    areas = {runner.entry.name: runner.entry.owned_image_area for runner in runtime.runners}
    annotated_area = AnnotatedArea.of(truth)
    misses = analyse_misses(images, numbers, region_lookup(areas), annotated_area)
    result = {"changes": changes, "ap50": round(evaluate(images).ap50, 4),
              "ap50_in_annotated_area": round(annotated_area.evaluate_inside(images).ap50, 4)}
    if misses is not None:
        summary = misses.summary()
        result.update(precision=summary["precision"], recall=summary["recall"], outcomes=summary["outcomes"],
                      recall_by_overlap=summary["recall_by_overlap"],
                      false_positive_kinds=misses.false_positive_kinds(),
                      near_miss_width_ratio=(misses.near_miss_errors()["width_ratio"] or {}).get("median"))
    if reference is not None:
        result["pose_agreement"] = pose_agreement(images, reference).to_dict()
    return result


def _table(results: dict[str, dict]) -> str:
    lines = ["| variant | AP50 | AP50 in the annotated area | precision | recall | near misses | missed | "
             f"recall apart | recall overlapping | false positives ({'/'.join(FALSE_POSITIVE_KINDS)}) | "
             "near-miss width ratio | pose agreement |", "|" + "---|" * 12]
    for name, r in results.items():
        overlap = r.get("recall_by_overlap", {})
        kinds = r.get("false_positive_kinds", {})
        lines.append(f"| {name} | {r['ap50']:.3f} | {r.get('ap50_in_annotated_area', '')} | "
                     f"{r.get('precision', 0):.3f} | {r.get('recall', 0):.3f} | "
                     f"{r.get('outcomes', {}).get('near miss', '')} | {r.get('outcomes', {}).get('missed', '')} | "
                     f"{overlap.get('apart', {}).get('recall', '')} | "
                     f"{overlap.get('overlapping another', {}).get('recall', '')} | "
                     f"{'/'.join(str(v) for v in kinds.values())} | {r.get('near_miss_width_ratio', '')} | "
                     f"{r.get('pose_agreement', {}).get('overall', '')} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange(1, 400, 5))
    parser.add_argument("--variant", nargs="+", action="append", metavar="NAME FIELD=VALUE",
                        help="a named variant and the DecodeConfig fields it changes (repeatable)")
    parser.add_argument("--external", type=Path, help="a YOLO-pose ONNX model: each variant's pose agreement with it")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    variants = {"bundle as exported": {}, **parse_variants(args.variant)}
    runtime = Runtime(args.bundle, parallel_regions=False)
    truth = read_mot_boxes(args.gt)
    numbers, maps = heatmaps_of(runtime, FrameSource(args.video, args.frames))
    reference = (reference_poses(args.external, FrameSource(args.video, args.frames), truth)
                 if args.external else None)
    results = {}
    for name, changes in variants.items():
        results[name] = measure(runtime, numbers, maps, truth, changes, reference)
        agreement = results[name].get("pose_agreement", {}).get("overall")
        print(f"{name:40s} AP50 {results[name]['ap50']:.3f}  recall {results[name].get('recall', 0):.3f}"
              + (f"  pose agreement {agreement:.3f}" if agreement is not None else ""))
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "decode_variants.json", {"bundle": str(args.bundle), "video": str(args.video),
                                                   "frames": str(args.frames), "reference": str(args.external),
                                                   "variants": results})
    (args.out / "decode_variants.md").write_text(_table(results))
    print(json.dumps({"written": str(args.out)}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
