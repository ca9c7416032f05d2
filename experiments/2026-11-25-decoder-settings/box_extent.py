"""Box height on real frames under the decoder's upright keypoint prior: today's (measured on the renders) or the
one before (``--before``, anatomical guesses that made every box about 6 % short).

Runs a bundle over a real clip (every frame, people down to 0.1 for the tracker) and prints AP50 each frame on its
own and tracked, and the median ratio of its boxes' heights to the ground truth's (pairs at IoU > 0.3, score
> 0.4). Results: results/box_extent.md.

    python experiments/2026-11-25-decoder-settings/box_extent.py BUNDLE --video CLIP --gt GT.txt [--last N] [--every K]
        [--fps F] [--before]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.decode import UPRIGHT_PRIOR, UprightPrior
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Person, Runtime, without_seam_duplicates
from vc.deploy.tracking import Tracker, tracking_rate
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.mot import read_mot_boxes

#: The upright prior of every bundle before 2026-11-26 (keypoints; the lower ankle's offset is the last one's).
BEFORE_OFFSETS = [-0.43, -0.45, -0.45, -0.44, -0.44, -0.32, -0.32, -0.15, -0.15, 0.0, 0.0, 0.02, 0.02, 0.25, 0.25,
                  0.46, 0.46]
BEFORE = UprightPrior(np.array(BEFORE_OFFSETS), BEFORE_OFFSETS[-1])


def _ap50(truth: dict, people: dict[int, list[Person]], frames: list[int]) -> float:
    return evaluate([ImageResult(truth_boxes=truth.get(n, np.zeros((0, 4))),
                                 boxes=np.array([p.box for p in people[n]]).reshape(-1, 4),
                                 scores=np.array([p.score for p in people[n]], float)) for n in frames]).ap50


def _height_ratio(truth: dict, people: dict[int, list[Person]], frames: list[int]) -> float:
    ratios = []
    for n in frames:
        truth_boxes = truth.get(n, np.zeros((0, 4)))
        boxes = np.array([p.box for p in people[n] if p.score > 0.4]).reshape(-1, 4)
        if not (len(truth_boxes) and len(boxes)):
            continue
        overlaps = box_iou(truth_boxes, boxes)
        for index, best in enumerate(overlaps.argmax(axis=1)):
            if overlaps[index, best] > 0.3:
                ratios.append((boxes[best, 3] - boxes[best, 1]) / (truth_boxes[index, 3] - truth_boxes[index, 1]))
    return float(np.median(ratios))


def _people(runtime: Runtime, frame: np.ndarray, prior: UprightPrior) -> list[Person]:
    """A frame's people as the runtime reports them, decoded with ``prior``."""
    people = [person for runner in runtime.runners for person in runner.people_in(runner.heatmaps(frame), prior=prior)]
    return without_seam_duplicates(sorted(people, key=lambda person: -person.score))


def measure(bundle: Path, video: Path, gt: Path, last: int, every: int, fps: float | None,
            prior: UprightPrior = UPRIGHT_PRIOR) -> dict:
    truth = read_mot_boxes(gt)
    source = FrameSource(video, FrameRange(1, last, 1))
    rate = tracking_rate(source, fps)
    with Runtime(bundle, threads=2, weak_people_above=0.1) as runtime:
        decoded = [(frame.number, _people(runtime, frame.image, prior)) for frame in source]
    scored = [n for n, _ in decoded if (n - 1) % every == 0 and n <= max(truth)]
    tracker = Tracker()
    tracked = {n: tracker.update(people, n / rate) for n, people in decoded}
    single = {n: [p for p in people if not p.weak] for n, people in decoded}
    return {"ap50_each_frame": round(_ap50(truth, single, scored), 4),
            "ap50_tracked": round(_ap50(truth, tracked, scored), 4),
            "height_ratio_median": round(_height_ratio(truth, tracked, scored), 3)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True, help="a video or a folder of frames")
    parser.add_argument("--gt", type=Path, required=True, help="MOT boxes")
    parser.add_argument("--last", type=int, default=100_000, help="last frame run")
    parser.add_argument("--every", type=int, default=1, help="score every K-th frame")
    parser.add_argument("--fps", type=float, help="frame rate of a folder of frames")
    parser.add_argument("--before", action="store_true", help="the upright prior before it was measured")
    args = parser.parse_args()
    prior = BEFORE if args.before else UPRIGHT_PRIOR
    result = measure(args.bundle, args.video, args.gt, args.last, args.every, args.fps, prior)
    print(json.dumps({"bundle": str(args.bundle), "prior": "before" if args.before else "measured", **result}))


if __name__ == "__main__":
    main()
