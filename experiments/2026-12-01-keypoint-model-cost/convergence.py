"""How quickly does the keypoint model learn? vc.model.crop_pose's training at a fixed number of crops seen, with
its squared error or with squared error weighted toward each target's peak, at its learning rate or a higher one,
in batches of 64 or fewer; held-out PCKh in image order (frozen, issue 57).

    PYTHONPATH=src python experiments/2026-12-01-keypoint-model-cost/convergence.py RENDERS SEED WIDTHS SAMPLES \
        LOSS PEAK_WEIGHT LEARNING_RATE BATCH [OUT] >> results/convergence.jsonl

LOSS: "mse" (vc.model.crop_pose today) or "weighted" (each cell's squared error times 1 + PEAK_WEIGHT * target).
OUT, when given, receives the model as the bundle ships it (OUT/crop_pose.onnx).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import torch

from vc.model.crop_pose import (
    LOSS_SCALE,
    CropPoseNet,
    _batch,
    dataset_crops,
    heatmap_targets,
    mirrored,
    pckh,
    read_keypoints,
)
from vc.model.export import export_crop_pose
from vc.model.facing import camera_look


def main() -> None:
    renders, seed = Path(sys.argv[1]), int(sys.argv[2])
    widths = tuple(int(w) for w in sys.argv[3].split(","))
    samples, loss_kind, peak_weight = int(sys.argv[4]), sys.argv[5], float(sys.argv[6])
    learning_rate, batch = float(sys.argv[7]), int(sys.argv[8])
    out = Path(sys.argv[9]) if len(sys.argv) > 9 else None
    train, held_out = dataset_crops(renders, seed, 80.0)
    start = time.perf_counter()
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = CropPoseNet(widths)
    steps = samples // batch
    optimiser = torch.optim.AdamW(net.parameters(), learning_rate / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, learning_rate, total_steps=steps)
    order = np.zeros(0, int)
    net.train()
    for _ in range(steps):
        if len(order) < batch:
            order = rng.permutation(len(train))
        chosen, order = order[:batch], order[batch:]
        looks = np.stack([camera_look(crop, rng) for crop in train.crops[chosen]])
        keypoints = train.keypoints[chosen]
        flip = rng.random(len(chosen)) < 0.5
        looks[flip], keypoints[flip] = mirrored(looks[flip], keypoints[flip])
        targets, labelled = heatmap_targets(keypoints)
        squared = (net(_batch(looks)) - targets) ** 2
        if loss_kind == "weighted":
            squared = squared * (1.0 + peak_weight * targets)
        error = squared.mean(dim=(2, 3))
        loss = (error * labelled).sum() / labelled.sum().clamp(min=1.0)
        optimiser.zero_grad()
        (loss * LOSS_SCALE).backward()
        optimiser.step()
        schedule.step()
    seconds = time.perf_counter() - start
    read = read_keypoints(net, held_out.crops)
    overall, per = pckh(read, held_out)
    sure = float((read[..., 2] >= 0.3).mean())
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        (out / "crop_pose.onnx").write_bytes(export_crop_pose(net))
    print(json.dumps({"renders": str(renders), "seed": seed, "widths": list(widths), "samples": samples,
                      "loss": loss_kind, "peak_weight": peak_weight, "learning_rate": learning_rate, "batch": batch,
                      "train_crops": len(train), "held_out_crops": len(held_out), "seconds": round(seconds, 1),
                      "held_out_pckh": round(overall, 4), "share_sure": round(sure, 3),
                      "per_keypoint": per, "out": None if out is None else str(out)}), flush=True)


if __name__ == "__main__":
    main()
