"""Do the region networks place keypoints nearer the reference on real people with more weight on the pose loss?
(frozen; issue 57 item 4's other part: where the keypoints sit)

    PYTHONPATH=src python experiments/2026-12-02-pose-weight/retrain.py COMPILE_DIR WEIGHT OUT

Trains every region of a compile again on its own renders with its own settings and seed (COMPILE_DIR's
``compile_config.yaml``), the loss's pose weight set to WEIGHT (``vc.model.loss.LossWeights.pose``, shipped 10: it
makes up for a keypoint Gaussian's tenth of a centre Gaussian's area and was never measured on real frames), into
OUT/run. The facing and keypoint models are trained on the renders alone, not on the region networks, so they are
copied from COMPILE_DIR/run. OUT/bundle is then exported as the compile exported it (precision auto, the scene named
in COMPILE_DIR/compile.json).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

from vc.model.trainer import data_workers, select_device
from vc.stages.config import read_config
from vc.stages.train import TrainingJob, _regions

PERSON_MODELS = ("facing.onnx", "facing.json", "crop_pose.onnx", "crop_pose.json")


def main() -> None:
    compile_dir, weight, out = Path(sys.argv[1]), float(sys.argv[2]), Path(sys.argv[3])
    config = read_config(compile_dir / "compile_config.yaml")
    settings = config.train
    train_config = settings.train_config()
    train_config = replace(train_config, loss=replace(train_config.loss, pose=weight))
    run, dataset = out / "run", compile_dir / "renders"
    run.mkdir(parents=True, exist_ok=True)
    for name in PERSON_MODELS:
        if (compile_dir / "run" / name).is_file():
            shutil.copy2(compile_dir / "run" / name, run / name)
    device = select_device()
    workers = data_workers(device) if settings.workers == "auto" else settings.workers
    TrainingJob(dataset, _regions(dataset, None), settings, train_config, device, workers).run(run)
    scene = compile_dir.parent / json.loads((compile_dir / "compile.json").read_text())["settings"]["scene"]
    subprocess.run(["vc-export", str(run), "-o", str(out / "bundle"), "--scene", str(scene), "--precision",
                    config.export.precision, "--eval-samples", str(config.export.eval_samples),
                    "--calibration-samples", str(config.export.calibration_samples), "--quiet"], check=True)


if __name__ == "__main__":
    main()
