"""The facing classifier retrained on a compile's renders with every person labelled by the pairs' vote (frozen,
issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-pairs-in-profile/train_arm.py RENDERS SEED OUT_DIR [ARM]

The classifier as shipped learns front from behind on people whose shoulders and hips agree on it and are far enough
apart (vc.model.facing.seen_from_front); people in profile get no label, and at runtime a logit they were never taught.
What the runtime needs from it is one bit a person: whether all eight pairs, each in image order, are read in the
order seen from behind (vc.deploy.facing step 3). Here each person's label is that bit as the keypoints vote: every
pair whose members lie further apart than the agreement's reach (half a head size, vc.evaluation.agreement) votes its
image order with its two keypoints, and the majority labels the person; people whose pairs all lie within reach, or
tie, stay unlabelled. With ARM ``shipped`` the labels are the shipped ones (the control: it reproduces the compile's
classifier). With ARM ``more K`` the labels are the shipped ones and K more classifiers are trained, with the seeds
SEED + 1 .. SEED + K (their initial weights, the crops' order and looks): the compile's classifier (SEED) and these
are the members of an ensemble. Writes OUT_DIR/front.onnx (or front_SEED+k.onnx: the classifier alone,
vc.model.export.export_facing) and OUT_DIR/front.json.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

import vc.model.facing as facing
from vc.deploy.heatmaps import PAIRS
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT
from vc.model.export import export_facing

SHIPPED = facing.seen_from_front
TALLY = {"labelled both ways": 0, "the vote disagrees with the torso": 0, "profile, labelled by the vote": 0,
         "unlabelled": 0}


def by_the_pairs(annotation: dict) -> bool | None:
    """Seen from the front (True), behind (False), or None: the pairs' vote (the module docstring)."""
    labels = np.reshape(annotation["keypoints"], (-1, 3))
    reach = AGREEMENT_HEAD_SIZES * HEAD_FRACTION_OF_HEIGHT * annotation["amodal_bbox"][3]
    votes = 0
    for index, (left, right) in enumerate(PAIRS):
        if labels[left, 2] <= 0 or labels[right, 2] <= 0:
            continue
        if np.hypot(*(labels[left, :2] - labels[right, :2])) > reach:
            votes += 2 if annotation["left_is_image_left"][index] else -2
    label = None if votes == 0 else votes < 0  # behind: the left members on the image's left
    torso = SHIPPED(annotation)
    if label is None:
        TALLY["unlabelled"] += 1
    elif torso is None:
        TALLY["profile, labelled by the vote"] += 1
    else:
        TALLY["labelled both ways"] += 1
        TALLY["the vote disagrees with the torso"] += int(torso != label)
    return label


def main() -> None:
    renders, seed, out = Path(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3])
    arm = sys.argv[4] if len(sys.argv) > 4 else "the pairs' vote"
    more = int(arm.split()[1]) if arm.startswith("more ") else 0
    if arm != "shipped" and not more:
        facing.seen_from_front = by_the_pairs
    train, held_out = facing.dataset_crops(renders)
    out.mkdir(parents=True, exist_ok=True)
    reports = []
    for member_seed in range(seed + 1, seed + more + 1) if more else [seed]:
        result = facing.train_facing(train.facing, held_out.facing, member_seed, show_progress=False)
        (out / (f"front_{member_seed}.onnx" if more else "front.onnx")).write_bytes(export_facing(result.net))
        reports.append({"renders": str(renders), "seed": member_seed, "arm": arm, **result.to_dict(),
                        "labels": TALLY if arm == "the pairs' vote" else None})
        print(json.dumps(reports[-1]), flush=True)
    (out / "front.json").write_text(json.dumps(reports, indent=1))


if __name__ == "__main__":
    main()
