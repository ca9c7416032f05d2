"""The keypoint model (vc.model.crop_pose) trained on a compile's renders with its seed, as vc-train trains it, but
for more crops seen or with wider layers, at the precision vc-train would choose, in a copy of the compile's bundle
(frozen experiment, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/train_arm.py RENDERS SEED CONTROL_BUNDLE \
        SAMPLES WIDTHS WORK >> experiments/2026-12-02-keypoint-model-capacity/results/training.jsonl

WIDTHS: four comma-separated widths (shipped: 16,24,48,64; SAMPLES shipped: 200000). WORK receives run/ (the model
and its report) and bundle/ (CONTROL_BUNDLE with this model in place of its own).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from vc.deploy.bundle import MANIFEST
from vc.deploy.crop_pose import MIN_READ_HEIGHT_PX
from vc.model.crop_pose import CROP_POSE_MODEL, CROP_POSE_REPORT, TRAINED_HEIGHT_SHARE, dataset_crops, train_crop_pose
from vc.model.crop_precision import keypoints_at_int8
from vc.model.export import export_crop_pose, with_crop_pose, write_bundle


def bundle_with(control: Path, run: Path, adding, out: Path) -> None:
    """``control``'s bundle with ``run``'s model put in by ``adding`` (``vc.model.export.with_crop_pose`` or
    ``with_facing``), written to ``out``."""
    manifest = json.loads((control / MANIFEST).read_text())
    files = {str(path.relative_to(control)): path.read_bytes() for path in control.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    write_bundle(*adding(manifest, files, run), out, as_zip=False)


def main() -> None:
    renders, seed, control = Path(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3])
    samples, widths, work = int(sys.argv[4]), tuple(int(w) for w in sys.argv[5].split(",")), Path(sys.argv[6])
    run, out = work / "run", work / "bundle"
    run.mkdir(parents=True, exist_ok=True)
    train, held_out = dataset_crops(renders, seed, TRAINED_HEIGHT_SHARE * MIN_READ_HEIGHT_PX)
    result = train_crop_pose(train, held_out, seed, samples=samples, widths=widths, show_progress=False)
    chosen = keypoints_at_int8(export_crop_pose(result.net), train, held_out, seed)
    (run / CROP_POSE_MODEL).write_bytes(chosen.model)
    report = {**result.to_dict(), "precision": chosen.precision,
              "held_out_pckh_by_precision": {k: None if v is None else round(v, 4) for k, v in chosen.measured.items()}}
    (run / CROP_POSE_REPORT).write_text(json.dumps(report, indent=1))
    bundle_with(control, run, with_crop_pose, out)
    print(json.dumps({"renders": str(renders), "seed": seed, "samples": samples, "widths": list(widths),
                      "work": str(work), **{k: v for k, v in report.items() if k != "held_out_pckh_per_keypoint"},
                      "held_out_pckh_per_keypoint": result.held_out_pckh_per_keypoint}), flush=True)


if __name__ == "__main__":
    main()
