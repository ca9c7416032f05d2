"""Does a person behind show a head or shoulders of their own? Each person the behind maps add
(``../2026-12-03-second-person/``) scored by what the keypoint maps show where their head and shoulders would be,
away from the decoded people's own (frozen probe, issue 57 item 2).

    PYTHONPATH=../../src:../2026-12-03-second-person python evidence.py BUNDLE HALF --seed S -o results

Why: the behind score fires on most people in front on real frames, whether anyone stands behind them or not. A
person an annotator boxes behind another is seen somewhere, mostly their head beside the front person's. If the
keypoint maps peak where the added person's head would be, and the decoded people's heads are not there, that is
evidence of someone the front person hides only in part.

Each frame on its own, the bundle's people as shipped (the numpy decoder), the added people (T = 0.3) with these
features (carried to the frame in the confidences of their first four keypoints, which nothing after the decoder
reads for a weak person):

- ``strength``: the behind score, as the second-person probe scored them;
- ``head``: the keypoint maps' highest value (nose, eyes, ears) within ``WINDOW`` heights of where the added
  person's head would stand upright, cells within ``CLAIMED`` heights of a decoded person's head keypoint left out;
- ``shoulders``: the same for the shoulders;
- ``sideways``: how far the added person's centre stands to the side of the front person's, in heights.

An added person is someone when their box overlaps at IoU >= 0.5 a person the bundle's own people did not match
(greedy by score). Writes ``results/seedS_HALF.jsonl``: one line an added person, its features and label.
"""

from __future__ import annotations

import argparse
import json
import threading
from pathlib import Path

import numpy as np
import real
import second_person

import vc.deploy.decode as decoding
import vc.deploy.runtime as runtime_module
from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.mot import read_mot_boxes

VIDEO = Path("../../../shared/data/tud_stadtmitte/frames")
GROUND_TRUTH = Path("../../../shared/data/tud_stadtmitte/gt_world.txt")
HALVES = {"choosing": "1:90", "confirming": "91:179"}
THRESHOLD = 0.3
FEATURES = ("strength", "head", "shoulders", "sideways")
HEAD_CHANNELS, SHOULDER_CHANNELS = (1, 2, 3, 4, 5), (6, 7)
HEAD_OFFSET, SHOULDER_OFFSET = -0.42, -0.305  # heights above the centre (vc.deploy.decode.UPRIGHT_OFFSETS)
WINDOW = 0.1  # heights around the expected point
CLAIMED = 0.07  # heights around a decoded person's keypoint

_LOCAL = threading.local()


def _window_max(maps, channels, point, radius, claimed):
    """The maps' highest value within ``radius`` cells of ``point``, claimed cells left out."""
    _, height, width = maps.shape
    rows, columns = np.mgrid[0:height, 0:width]
    near = np.hypot(columns - point[0], rows - point[1]) <= radius
    free = near & ~claimed
    if not free.any():
        return 0.0
    return float(maps[list(channels)][:, free].max())


def _claimed(shape, front, stride, channels):
    """Cells within CLAIMED heights of the decoded people's keypoints of ``channels`` (anatomical indices)."""
    height, width = shape
    rows, columns = np.mgrid[0:height, 0:width]
    claimed = np.zeros(shape, bool)
    for person in front:
        person_height = (person.box[3] - person.box[1]) / stride
        radius = max(1.0, CLAIMED * person_height)
        for index in channels:
            x, y, confidence = person.keypoints[index - 1]
            if confidence < 0.2:
                continue
            cx, cy = (x + 0.5) / stride - 0.5, (y + 0.5) / stride - 0.5
            claimed |= np.hypot(columns - cx, rows - cy) <= radius
    return claimed


def _find_peaks(heatmap, threshold, limit=None):
    """``second_person``'s peaks (the people behind added), each added one given its features, kept in the map."""
    own = len(second_person._FIND_PEAKS(heatmap, threshold, limit))
    pending = getattr(second_person._CURRENT, "pending", None)
    peaks = second_person._find_peaks_behind(heatmap, threshold, limit)
    if pending is None or len(peaks) == own:
        return peaks
    maps, config, expected, _ = pending
    stride = config.stride
    front = _LOCAL.front
    fronts = np.array([peak[1] for peak in peaks[:own]], float)
    head_claimed = _claimed(maps.shape[1:], front, stride, HEAD_CHANNELS)
    shoulder_claimed = _claimed(maps.shape[1:], front, stride, SHOULDER_CHANNELS)
    height, width = heatmap.shape[-2:]
    result = list(peaks[:own])
    for strength, point in peaks[own:]:
        point = np.clip(point, 0, [width - 1, height - 1])
        person_height = second_person._heights_cells_at(point[None], expected, stride)[0]
        nearest = fronts[np.argmin(np.hypot(*(fronts - point).T))]
        radius = max(1.5, WINDOW * person_height)
        features = {
            "strength": float(strength),
            "head": _window_max(maps, HEAD_CHANNELS, point + [0, HEAD_OFFSET * person_height], radius, head_claimed),
            "shoulders": _window_max(maps, SHOULDER_CHANNELS, point + [0, SHOULDER_OFFSET * person_height], radius,
                                     shoulder_claimed),
            "sideways": float(abs(point[0] - nearest[0]) / person_height),
        }
        _LOCAL.added.append((point, features))
        result.append((strength, point))
    return result


def decode_with_evidence(heatmaps, config, expected_height_px=None, weak_above=None, prior=decoding.UPRIGHT_PRIOR):
    """The people in front as decoded without the behind maps, then the added people, flagged weak, their features
    in their first keypoints' confidences."""
    _LOCAL.front = second_person._DECODE(heatmaps, config, expected_height_px, weak_above, prior)
    _LOCAL.added = []
    people = second_person.decode_behind(heatmaps, config, expected_height_px, weak_above, prior)
    front = len(_LOCAL.front)
    points = np.array([point for point, _ in _LOCAL.added], float).reshape(-1, 2)
    for person in people[front:]:
        person.weak = True
        cell = (np.asarray(person.centre) + 0.5) / config.stride - 0.5
        features = _LOCAL.added[int(np.argmin(np.hypot(*(points - cell).T)))][1]
        person.keypoints = person.keypoints.copy()
        person.keypoints[:len(FEATURES), 2] = [features[name] for name in FEATURES]
    return people


def added_people(bundle: Path, frames: str) -> list[dict]:
    """Every added person each frame, with its features, labelled against the truth."""
    truth = read_mot_boxes(GROUND_TRUTH)
    rows = []
    with Runtime(bundle, threads=2) as runtime:
        for frame in FrameSource(VIDEO, FrameRange.parse(frames)):
            people = runtime.run(frame.image).people
            boxes_truth = truth.get(frame.number, np.zeros((0, 4)))
            reported = sorted([p for p in people if not p.weak], key=lambda p: -p.score)
            free = np.ones(len(boxes_truth), bool)
            for person in reported:
                if not free.any():
                    break
                overlaps = box_iou(person.box, boxes_truth)[0] * free
                if overlaps.max() >= 0.5:
                    free[int(np.argmax(overlaps))] = False
            for person in (p for p in people if p.weak):
                overlaps = box_iou(person.box, boxes_truth)[0] if len(boxes_truth) else np.zeros(0)
                best = float((overlaps * free).max()) if len(overlaps) else 0.0
                rows.append({"frame": frame.number, "box": [round(float(v), 1) for v in person.box],
                             "someone": best >= 0.5, "best_iou_free": round(best, 3),
                             **{name: round(float(value), 4)
                                for name, value in zip(FEATURES, person.keypoints[:len(FEATURES), 2], strict=True)}})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("half", choices=sorted(HALVES))
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    real.install()
    decoding.find_peaks = _find_peaks
    runtime_module.decode = decode_with_evidence
    second_person.THRESHOLD[0] = THRESHOLD
    rows = added_people(args.bundle, HALVES[args.half])
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / f"seed{args.seed}_{args.half}.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    print(f"seed {args.seed} {args.half}: {len(rows)} added people, {sum(r['someone'] for r in rows)} someone")


if __name__ == "__main__":
    main()
