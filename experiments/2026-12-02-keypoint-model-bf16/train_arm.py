"""The keypoint model (vc.model.crop_pose) trained on a compile's renders with its seed for SAMPLES crops, its
forward pass in COMPUTE (fp32 | bf16-cl: bfloat16 autocast in channels-last, as the region networks train where the
CPU has bf16 instructions, docs/decisions/0006-training-compute.md), put in a copy of the compile's bundle (frozen
experiment, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-bf16/train_arm.py RENDERS SEED CONTROL_BUNDLE \
        SAMPLES COMPUTE WORK >> experiments/2026-12-02-keypoint-model-bf16/results/training.jsonl

WORK receives run/ (the model and its report) and bundle/ (CONTROL_BUNDLE with this model in place of its own).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

from vc.deploy.crop_pose import MIN_READ_HEIGHT_PX
from vc.model.crop_pose import CROP_POSE_MODEL, CROP_POSE_REPORT, TRAINED_HEIGHT_SHARE, dataset_crops, train_crop_pose
from vc.model.crop_precision import keypoints_at_int8
from vc.model.export import export_crop_pose, with_crop_pose

# The bundle is put together as the capacity experiment put it together (one function, not a copy of it).
_CAPACITY = Path(__file__).parents[1] / "2026-12-02-keypoint-model-capacity" / "train_arm.py"
_spec = importlib.util.spec_from_file_location("capacity_train_arm", _CAPACITY)
capacity = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(capacity)

COMPUTES = {"fp32": {"bf16_autocast": False, "channels_last": False},
            "bf16-cl": {"bf16_autocast": True, "channels_last": True}}


def main() -> None:
    renders, seed, control = Path(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3])
    samples, compute, work = int(sys.argv[4]), sys.argv[5], Path(sys.argv[6])
    run, out = work / "run", work / "bundle"
    run.mkdir(parents=True, exist_ok=True)
    train, held_out = dataset_crops(renders, seed, TRAINED_HEIGHT_SHARE * MIN_READ_HEIGHT_PX)
    result = train_crop_pose(train, held_out, seed, samples=samples, show_progress=False, **COMPUTES[compute])
    chosen = keypoints_at_int8(export_crop_pose(result.net), train, held_out, seed)
    (run / CROP_POSE_MODEL).write_bytes(chosen.model)
    report = {**result.to_dict(), "precision": chosen.precision,
              "held_out_pckh_by_precision": {k: None if v is None else round(v, 4) for k, v in chosen.measured.items()}}
    (run / CROP_POSE_REPORT).write_text(json.dumps(report, indent=1))
    capacity.bundle_with(control, run, with_crop_pose, out)
    print(json.dumps({"renders": str(renders), "seed": seed, "samples": samples, "compute": compute,
                      "work": str(work), **{k: v for k, v in report.items() if k != "held_out_pckh_per_keypoint"},
                      "held_out_pckh_per_keypoint": result.held_out_pckh_per_keypoint}), flush=True)


if __name__ == "__main__":
    main()
