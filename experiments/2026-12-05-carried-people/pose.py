"""Pose agreement of a bundle tracked with one of :data:`measure.VARIANTS`'s tracker settings (carried people keep
the keypoints they were last seen with, moved by their motion, and are scored like everyone else).

    PYTHONPATH=src python experiments/2026-12-05-carried-people/pose.py CAMERA SEED 0|1 BUNDLE VARIANT --label COMPILE \
        >> experiments/2026-12-05-carried-people/results/pose_CAMERA.jsonl

Runs ``../2026-12-02-keypoint-model-capacity/measure.py``'s measurement (pose agreement with YOLO11n-pose @1280, each
frame on its own and tracked as ``vc-eval`` tracks) with its tracker given the variant's settings.
"""

from __future__ import annotations

import argparse
import functools
import importlib.util
import json
import sys
from dataclasses import replace
from pathlib import Path

from vc.deploy.tracking import TrackingConfig


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


HERE = Path(__file__).parent
capacity = _load("capacity", HERE.parent / "2026-12-02-keypoint-model-capacity" / "measure.py")
measure = _load("carried_measure", HERE / "measure.py")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera")
    parser.add_argument("seed", type=int)
    parser.add_argument("half", type=int, choices=(0, 1))
    parser.add_argument("bundle", type=Path)
    parser.add_argument("variant")
    parser.add_argument("--label", default="")
    args = parser.parse_args()
    fields, covered = measure.VARIANTS[args.variant]
    if covered is not None:
        raise SystemExit("pose.py runs the variants of TrackingConfig fields only")
    capacity.TrackingConfig = functools.partial(replace, TrackingConfig(), **fields)
    first, last, step = capacity.CAMERAS[args.camera][3][args.half]
    result = capacity.half({args.variant: args.bundle}, args.camera, first, last, step)
    print(json.dumps({"camera": args.camera, "seed": args.seed, "compile": args.label, "variant": args.variant,
                      **result}), flush=True)


if __name__ == "__main__":
    main()
