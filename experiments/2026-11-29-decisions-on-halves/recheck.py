"""Decisions taken on all of PETS09's 400 dev frames (and all of TUD-Stadtmitte), re-checked the way issue 57 asks:
each setting at today's value against the value it replaced (or the alternative its record measured), on the
choosing halves (PETS09 1-200, TUD-Stadtmitte 1-90) and the confirming halves (201-400, 91-179), three compile
seeds, int8 bundles as shipped. Only settings that need no retraining are re-checked here: the decoder's (a copy of
the bundle whose manifest's ``decode`` differs), the runtime's seam rules and the tracker's (frozen experiment).

    python experiments/2026-11-29-decisions-on-halves/recheck.py pets BUNDLE0 BUNDLE1 BUNDLE2 -o results/pets
    python experiments/2026-11-29-decisions-on-halves/recheck.py tud BUNDLE0 BUNDLE1 BUNDLE2 -o results/tud

Writes one JSON per variant, seed and half (``VARIANT/seedS_HALF.json``): AP50 tracked and each frame, CLEAR MOT,
recall of people overlapping another; a finished file is not run again (resumable).
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import shutil
import tempfile
from dataclasses import dataclass, field, replace
from pathlib import Path

import vc.deploy.runtime as runtime
from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
CAMERAS = {
    "pets": {"video": DATA / "pets09_s2l1" / "vtest.avi", "gt": DATA / "pets09_s2l1" / "gt_dev_frames_0001-0400.txt",
             "fps": None, "halves": {"choosing": "1:200:5", "confirming": "201:400:5"}},
    "tud": {"video": DATA / "tud_stadtmitte" / "frames", "gt": DATA / "tud_stadtmitte" / "gt_world.txt",
            "fps": 25.0, "halves": {"choosing": "1:90", "confirming": "91:179"}},
}


@dataclass(frozen=True)
class Variant:
    """One setting away from today's: its decision record, the decode fields, seam rules or tracker fields."""

    record: str
    decode: dict = field(default_factory=dict)
    seam_duplicate_iou: float | None = None
    seam_foot_tolerance: float | None = None
    across_seam_duplicate_iou: float | None = None
    tracking: dict = field(default_factory=dict)


VARIANTS = {
    "today": Variant("-"),
    # 0003: votes 0.15 with each keypoint peak to one person, against 0.3 (tracked AP50 on all 400 frames)
    "vote_support_0.3": Variant("0003", decode={"vote_support": 0.3}),
    # 0003: reach sideways 0.2 against 0.3 (the value it replaced)
    "reach_sideways_0.3": Variant("0003", decode={"reach_sideways": 0.3}),
    # 0003: centre peaks closer than 0.15 heights are one person, against 0.10 and 0.25
    "separation_0.10": Variant("0003", decode={"min_centre_separation": 0.10}),
    "separation_0.25": Variant("0003", decode={"min_centre_separation": 0.25}),
    # 0003: head and ankles within 1.5x of the expected height, against 1.25
    "height_range_1.25": Variant("0003", decode={"keypoint_height_range": 1.25}),
    # 0003: side margin 0.03 kept against 0.015
    "side_margin_0.015": Variant("0003", decode={"side_margin": 0.015}),
    # 0003: seam rules against none (duplicates across a seam kept, feet exactly in the owned area, the stronger wins)
    "seam_duplicates_off": Variant("0003", seam_duplicate_iou=1.01),
    "seam_tolerance_0": Variant("0003", seam_foot_tolerance=0.0),
    "across_seam_0.6": Variant("0003", across_seam_duplicate_iou=0.6),
    # 0007: clothing colours weigh 0.3 in the association, against motion alone
    "appearance_weight_0": Variant("0007", tracking={"appearance_weight": 0.0}),
    # 0007: weak peaks continue tracks, and lost people are carried 0.5 s, against neither
    "weak_people_off": Variant("0007", tracking={"weak_people_above": None}),
    "coast_0": Variant("0007", tracking={"coast_s": 0.0}),
}


def variant_bundle(bundle: Path, variant: Variant, work: Path) -> Path:
    """``bundle`` itself, or a copy (models hard-linked) whose regions decode with the variant's fields."""
    if not variant.decode:
        return bundle
    copy = work / bundle.name
    if not copy.exists():
        shutil.copytree(bundle, copy, copy_function=os.link)
        manifest_path = copy / "manifest.json"
        manifest = json.loads(manifest_path.read_text())
        for region in manifest["regions"]:
            region["decode"].update(variant.decode)
        manifest_path.unlink()  # a hard link: the original's manifest stays as it is
        manifest_path.write_text(json.dumps(manifest, indent=1))
    return copy


def patched_runtime(variant: Variant):
    """The runtime's seam rules as the variant has them (module state, restored by the caller)."""
    saved = (runtime.without_seam_duplicates, runtime.ACROSS_SEAM_DUPLICATE_IOU,
             runtime.RegionRunner.people_in.__defaults__)
    if variant.seam_duplicate_iou is not None:
        runtime.without_seam_duplicates = functools.partial(saved[0], iou=variant.seam_duplicate_iou)
    if variant.across_seam_duplicate_iou is not None:
        runtime.ACROSS_SEAM_DUPLICATE_IOU = variant.across_seam_duplicate_iou
    if variant.seam_foot_tolerance is not None:
        runtime.RegionRunner.people_in.__defaults__ = (None, variant.seam_foot_tolerance, *saved[2][2:])
    return saved


def restore_runtime(saved) -> None:
    runtime.without_seam_duplicates, runtime.ACROSS_SEAM_DUPLICATE_IOU = saved[0], saved[1]
    runtime.RegionRunner.people_in.__defaults__ = saved[2]


def measure(camera: str, bundle: Path, variant: Variant, frames: str, output: Path) -> dict:
    spec = CAMERAS[camera]
    request = EvaluationRequest(bundle=bundle, video=spec["video"], ground_truth=spec["gt"], output=output,
                                frames=FrameRange.parse(frames), hog=False, threads=2,
                                tracking=replace(TrackingConfig(), **variant.tracking), fps=spec["fps"])
    saved = patched_runtime(variant)
    try:
        report = evaluate_bundle(request, show_progress=False)
    finally:
        restore_runtime(saved)
    metrics, misses = report.metrics, report.misses
    overlapping = misses.recall_by_group().get("overlapping another") if misses is not None else None
    return {"frames": frames, "ap50_tracked": metrics["detectors"][OURS]["ap50"],
            "ap50_each_frame": metrics["detectors"][OURS_SINGLE_FRAME]["ap50"],
            "tracking": metrics["tracking"].get("accuracy"),
            "overlapping_recall": None if overlapping is None else overlapping["recall"],
            "precision": None if misses is None else misses.precision,
            "recall": None if misses is None else misses.recall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(CAMERAS))
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--variants", nargs="*", default=list(VARIANTS))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.variants:
            variant = VARIANTS[name]
            for seed, bundle in enumerate(args.bundles):
                work = Path(scratch) / name / f"seed{seed}"
                work.mkdir(parents=True, exist_ok=True)
                for half, frames in CAMERAS[args.camera]["halves"].items():
                    target = args.out / name / f"seed{seed}_{half}.json"
                    if target.exists():
                        continue
                    result = measure(args.camera, variant_bundle(bundle, variant, work), variant, frames,
                                     work / half)
                    target.parent.mkdir(parents=True, exist_ok=True)
                    target.write_text(json.dumps({"variant": name, "record": variant.record, "seed": seed,
                                                  "half": half, "bundle": str(bundle), **result}, indent=1))
                    print(f"{name:22s} seed {seed} {half:10s} tracked {result['ap50_tracked']:.3f} each frame "
                          f"{result['ap50_each_frame']:.3f}", flush=True)


if __name__ == "__main__":
    main()
