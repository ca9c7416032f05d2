"""What the weather and gain ranges cost a training step: the training stream's windows under the camera range of
decision 0014 (exposure, white balance, night IR, a Gaussian blur, compression) and under today's (with gain noise,
veil, rain and snow, defocus and shake besides), interleaved in one process, and one optimiser step of the standard
network, on a rendered region (frozen experiment, issue 62).

    python experiments/2026-11-29-weather-and-gain/training_cost.py RENDERS [--region r1] [--items 400] [--steps 20]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import torch

from vc.cores import cpu_facts
from vc.model.camera_range import CameraRange, camera_life_of
from vc.model.data import TrainingStream
from vc.model.loss import scene_pose_loss
from vc.model.network import ScenePoseNet
from vc.model.trainer import forward, memory_format, select_device
from vc.render.dataset import open_region
from vc.stages.config import PRESETS

RESULTS = Path(__file__).parent / "results"
#: The range as decision 0014 shipped it: today's fields that did not exist then, off.
RANGE_0014 = CameraRange(blurred=0.25, defocus_px=0.0, shake_px=0.0, noisy=0.0, veiled=0.0, precipitation=0.0)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("renders", type=Path)
    parser.add_argument("--region", default="r1")
    parser.add_argument("--items", type=int, default=400)
    parser.add_argument("--steps", type=int, default=20)
    args = parser.parse_args()
    select_device()
    config = PRESETS["standard"].train.train_config()
    data = open_region(args.renders, args.region)

    def stream(camera_range: CameraRange | None) -> TrainingStream:
        life = None if camera_range is None else camera_life_of(data.manifest, data.region, camera_range,
                                                                config.seed)
        return TrainingStream(data.train, config.codec, data.input_size, config.crop, config.augmentation,
                              config.seed, camera_life=life)

    streams = {"none": stream(None), "0014": stream(RANGE_0014), "today": stream(CameraRange())}
    for each in streams.values():  # decode every sample once: the cache, as in training
        for draw in range(len(each)):
            each[draw]
    seconds = {name: 0.0 for name in streams}
    for block in range(0, args.items, 20):  # interleaved blocks of 20 windows
        for name, each in streams.items():
            started = time.perf_counter()
            for draw in range(block, block + 20):
                each[len(each) + draw]
            seconds[name] += time.perf_counter() - started
    per_item = {name: 1000 * value / args.items for name, value in seconds.items()}
    net = ScenePoseNet(config.network).to(memory_format=memory_format(config))
    optimiser = torch.optim.AdamW(net.parameters(), lr=config.learning_rate)
    batch = [streams["none"][draw] for draw in range(config.batch_size)]
    images = torch.stack([item[0] for item in batch]).to(memory_format=memory_format(config))
    targets = torch.stack([item[1] for item in batch])
    step_times = []
    for _ in range(args.steps):
        started = time.perf_counter()
        outputs = forward(net, images, config)
        loss, _ = scene_pose_loss(outputs, targets, config.loss)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        step_times.append(time.perf_counter() - started)
    step_ms = 1000 * float(np.median(step_times[2:]))
    step = {name: config.batch_size * value + step_ms for name, value in per_item.items()}
    report = {"machine": cpu_facts()[0], "region": args.region, "window": list(config.crop.size),
              "items": args.items, "ms_per_window": {k: round(v, 3) for k, v in per_item.items()},
              "ms_per_step_network": round(step_ms, 1), "batch_size": config.batch_size,
              "training_step_ratio": {"today / 0014": round(step["today"] / step["0014"], 3),
                                      "today / none": round(step["today"] / step["none"], 3)}}
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "training_cost.json").write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
