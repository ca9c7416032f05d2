"""Who is still read with left and right the other way round, tracked, and what ordered them: the walk, the track's
vote, or the networks (frozen, issue 57; after decision 0049).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted \
        python experiments/2026-12-02-who-is-swapped/swapped.py BUNDLE SEED CAMERA >> results/swapped.jsonl

Runs the bundle as shipped with the shipped tracker (main at 1e56ccc) over each half, and scores every person both
it and YOLO11n-pose @1280 found at their operating points as vc.evaluation.agreement does (steps 1, 2 and 4).
A person counts as swapped where more of the reference's confident keypoints agree with their pairs exchanged,
and as ordered by their pairs otherwise (ties count as not swapped). Each person is tallied by ``person.facing``,
by height (under 100 px, 100 px and taller). One JSON line
per half: counts of people and of swapped people per cell, and the agreement each cell loses to the swap (keypoints
that would agree exchanged, less those that agree as read, over all keypoints compared in the half).
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import arms as voted  # experiments/2026-12-02-small-people-voted/arms.py: data, reference, halves
import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, matched_people
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult
from vc.evaluation.mot import read_mot_boxes


def half(bundle: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = voted.DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(voted.REFERENCE), threads=2)
    tracker = Tracker(TrackingConfig())
    ours, theirs, facings = [], [], []
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as run:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = run.run(frame.image)
            people = result.reported(tracker.update(result.people, frame.number / fps, frame.image))
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            ours.append(voted._image(boxes, people))
            facings.append([(p.facing, p.box[3] - p.box[1]) for p in people])
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    people, swapped, lost = Counter(), Counter(), Counter()
    compared = 0
    for image, reference_image, facing, mine, their_matches in zip(ours, theirs, facings, matched_people(ours),
                                                                   matched_people(theirs), strict=True):
        for index in sorted(set(mine) & set(their_matches)):
            box = image.truth_boxes[index]
            head = HEAD_FRACTION_OF_HEIGHT * (box[3] - box[1])
            keypoints = np.asarray(image.keypoints[mine[index]], np.float64)
            reference_keypoints = np.asarray(reference_image.keypoints[their_matches[index]], np.float64)
            confident = reference_keypoints[:, 2] >= REFERENCE_CONFIDENCE
            agree, agree_exchanged = (
                int((confident & (np.linalg.norm(k[:, :2] - reference_keypoints[:, :2], axis=1)
                                  <= AGREEMENT_HEAD_SIZES * head)).sum())
                for k in (keypoints, swap_pairs(keypoints, [True] * len(PAIRS))))
            compared += int(confident.sum())
            source, height = facing[mine[index]]
            cell = f"{source}, {'100 px and taller' if height >= 100 else 'under 100 px'}"
            people[cell] += 1
            if agree_exchanged > agree:
                swapped[cell] += 1
                lost[cell] += agree_exchanged - agree
    return {cell: {"people": people[cell], "swapped": swapped[cell], "lost": round(lost[cell] / compared, 4)}
            for cell in sorted(people)}


def main() -> None:
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    for name, (first, last, step) in zip(voted.HALVES, voted.DATA[camera][3], strict=True):
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "cells": half(bundle, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
