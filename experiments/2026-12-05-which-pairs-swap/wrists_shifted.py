"""A diagnostic, not a change (frozen experiment, issue 57 item 4): how much of the tracked pose agreement do the
wrists' and elbows' vertical offsets from the reference cost? Every tracked person's wrists are moved up by 0.17 and
elbows by 0.07 head sizes (the medians vc-eval reports, ours below the reference's) and agreement is scored again.
The offsets are the real frames' own, so this bounds what removing a bias could give; it is not a setting.

    PYTHONPATH=../../src python wrists_shifted.py /tmp/pairs      # collect.py's tudS_HALF.pkl files
"""

from __future__ import annotations

import copy
import pickle
import sys
from pathlib import Path

import numpy as np

from vc.evaluation.agreement import pose_agreement
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult

#: (keypoint, head sizes up): the wrists and the elbows.
SHIFTS = ((9, 0.17), (10, 0.17), (7, 0.07), (8, 0.07))


def _image(frame: dict, people: list[dict]) -> ImageResult:
    return ImageResult(truth_boxes=frame["truth"], boxes=np.array([p["box"] for p in people]).reshape(-1, 4),
                       scores=np.array([p["score"] for p in people]),
                       keypoints=np.array([p["keypoints"] for p in people]).reshape(-1, 17, 3))


def main() -> None:
    folder = Path(sys.argv[1])
    for half in (0, 1):
        before, after = [], []
        for seed in range(3):
            frames = pickle.loads((folder / f"tud{seed}_{half}.pkl").read_bytes())
            theirs = [ImageResult(truth_boxes=f["truth"], **f["theirs"]) for f in frames]
            moved = []
            for frame in frames:
                people = copy.deepcopy(frame["ours"])
                for person in people:
                    height = person["box"][3] - person["box"][1]
                    for keypoint, up in SHIFTS:
                        person["keypoints"][keypoint][1] -= up * HEAD_FRACTION_OF_HEIGHT * height
                moved.append(_image(frame, people))
            before.append(pose_agreement([_image(f, f["ours"]) for f in frames], theirs).overall)
            after.append(pose_agreement(moved, theirs).overall)
        print(f"half {half}: tracked {np.round(before, 3)} -> {np.round(after, 3)}; "
              f"mean {np.mean(before):.3f} -> {np.mean(after):.3f}")


if __name__ == "__main__":
    main()
