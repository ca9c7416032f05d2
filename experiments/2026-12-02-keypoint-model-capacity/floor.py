"""measure.py with the keypoint model's peak floor (vc.deploy.crop_pose.PEAK_FLOOR, 0.3) set to FLOOR for every
bundle read: does the longer-trained model, surer of its keypoints, want another floor? (frozen experiment)

    PYTHONPATH=src python experiments/2026-12-02-keypoint-model-capacity/floor.py FLOOR CAMERA SEED HALF \
        NAME=BUNDLE ... >> experiments/2026-12-02-keypoint-model-capacity/results/floor.jsonl
"""

from __future__ import annotations

import sys

import measure

import vc.deploy.crop_pose

if __name__ == "__main__":
    floor = float(sys.argv.pop(1))
    vc.deploy.crop_pose.PEAK_FLOOR = floor
    print(f'{{"peak_floor": {floor}}}', flush=True)
    measure.main()
