"""Where a step of the keypoint model's training goes: 150 steps of vc.model.crop_pose.train_crop_pose on
TUD-Stadtmitte seed 0's crops under cProfile (frozen experiment).

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/profile_training.py RENDERS
"""

import cProfile
import pstats
import sys
from pathlib import Path

from vc.model.crop_pose import PoseCrops, dataset_crops, train_crop_pose

train, held_out = dataset_crops(Path(sys.argv[1]), 0, 80.0)
few = PoseCrops(held_out.crops[:64], held_out.keypoints[:64], held_out.heights[:64])
profile = cProfile.Profile()
profile.runcall(train_crop_pose, train, few, 0, samples=64 * 150, show_progress=False)
pstats.Stats(profile).sort_stats("tottime").print_stats(12)
