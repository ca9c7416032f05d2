"""The keypoint model's training, 100 steps of vc.model.crop_pose.train_crop_pose on TUD-Stadtmitte seed 0's crops,
under each of the trainer's four compute settings, twice, interleaved (frozen experiment).

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-bf16/time_compute.py RENDERS 100 \
        > experiments/2026-12-02-keypoint-model-bf16/results/step_times.txt
"""

import sys
import time
from pathlib import Path

import torch

from vc.model.crop_pose import BATCH, PoseCrops, dataset_crops, train_crop_pose

torch.set_num_threads(2)
train, held_out = dataset_crops(Path(sys.argv[1]), 0, 80.0)
few = PoseCrops(held_out.crops[:64], held_out.keypoints[:64], held_out.heights[:64])
steps = int(sys.argv[2])
for repetition in range(2):
    for name, bf16, channels_last in [("fp32", False, False), ("fp32 channels-last", False, True),
                                      ("bf16", True, False), ("bf16 channels-last", True, True)]:
        start = time.perf_counter()
        train_crop_pose(train, few, 0, samples=BATCH * steps, bf16_autocast=bf16, channels_last=channels_last,
                        show_progress=False)
        print(repetition, name, round(time.perf_counter() - start, 1), flush=True)
