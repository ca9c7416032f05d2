"""Where TUD-Stadtmitte's people overlapping another are lost (frozen probe): what the decoder's centre and head
readings, the head map at their head and the runtime's report make of each true person.

    PYTHONPATH=src python experiments/2026-12-05-head-union-iou/where_lost.py BUNDLE FIRST:LAST

Each true person is, in this order: reported (matched one to one, strongest first, at IoU >= 0.5); read by the
centre reading (a box of it at IoU >= 0.5) or by the head reading, and lost to the rules; seen by the head map (at
least the centre threshold within a cell of their head) with no box at IoU >= 0.5; seen by the centre map alone; or
by neither. For the people not reported, the head reading's person whose head (box top middle) is nearest theirs:
how far (in their heights) and that box's IoU, height and width over theirs.
"""

from __future__ import annotations

import sys
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import CENTRE_CHANNEL, HEAD_CHANNEL
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import grouped
from vc.evaluation.mot import read_mot_boxes

DATA = Path("../shared/data/tud_stadtmitte")
THRESHOLD = 0.3
HEAD_DOWN = 0.07  # the head's middle below the box's top, in the person's heights


def reported_ious(truth: np.ndarray, boxes: np.ndarray, scores: np.ndarray) -> np.ndarray:
    """Each true person's IoU with the reported box matched to them one to one, strongest first (0: none)."""
    matched = np.zeros(len(truth))
    if not len(boxes):
        return matched
    overlaps = box_iou(boxes, truth)
    for detection in np.argsort(-scores):
        free = [k for k in np.argsort(-overlaps[detection]) if not matched[k] and overlaps[detection, k] >= 0.5]
        if free:
            matched[free[0]] = overlaps[detection, free[0]]
    return matched


def map_at(runtime: Runtime, image: np.ndarray, points: np.ndarray) -> dict[str, np.ndarray]:
    """The decoder's two readings' boxes (frame pixels) and the head and centre maps' largest value within a cell of
    each of ``points`` ({"head": (N, 2), "centre": (N, 2)}), over the regions."""
    found = {"centre boxes": [], "head boxes": [], "head": np.zeros(len(points["head"])),
             "centre": np.zeros(len(points["centre"]))}
    for runner in runtime.runners:
        maps = runner.heatmaps(image)
        for person in runner.decode(maps, runner.entry.decode, runner.entry.expected_height_px, None):
            box = runner.to_frame(np.asarray(person.box).reshape(2, 2)).reshape(4)
            found["head boxes" if person.head_found else "centre boxes"].append(box)
        stride = runner.entry.decode.stride
        height, width = maps.shape[1:]
        for name, channel in (("head", HEAD_CHANNEL), ("centre", CENTRE_CHANNEL)):
            cells = ((points[name] - runner.origin + 0.5) * runner.scale - 0.5) / stride
            for index, (column, row) in enumerate(np.round(cells).astype(int)):
                if 0 <= column < width and 0 <= row < height:
                    window = maps[channel, max(row - 1, 0):row + 2, max(column - 1, 0):column + 2]
                    found[name][index] = max(found[name][index], float(window.max()))
    return found


def best_iou(truth: np.ndarray, boxes: list) -> np.ndarray:
    boxes = np.array(boxes).reshape(-1, 4)
    return box_iou(truth, boxes).max(axis=1) if len(boxes) else np.zeros(len(truth))


def main() -> None:
    bundle, frames = Path(sys.argv[1]), FrameRange.parse(sys.argv[2])
    truths = read_mot_boxes(DATA / "gt_world.txt")
    runtime = Runtime(bundle, threads=2)
    kinds: Counter = Counter()
    nearest: dict[str, list] = defaultdict(list)
    for frame in FrameSource(DATA / "frames", frames):
        truth = truths.get(frame.number, np.zeros((0, 4)))
        if not len(truth):
            continue
        people = [person for person in runtime.run(frame.image).people if not person.weak]
        heights = truth[:, 3] - truth[:, 1]
        middles = (truth[:, 0] + truth[:, 2]) / 2
        heads = np.column_stack([middles, truth[:, 1] + HEAD_DOWN * heights])
        found = map_at(runtime, frame.image, {"head": heads,
                                              "centre": np.column_stack([middles, (truth[:, 1] + truth[:, 3]) / 2])})
        reported = reported_ious(truth, np.array([p.box for p in people]).reshape(-1, 4),
                                 np.array([p.score for p in people]))
        centre_read, head_read = best_iou(truth, found["centre boxes"]), best_iou(truth, found["head boxes"])
        head_boxes = np.array(found["head boxes"]).reshape(-1, 4)
        for k in np.flatnonzero(grouped(truth)):
            if reported[k] >= 0.5:
                kinds["reported"] += 1
                continue
            kind = ("read by the centre reading, lost to the rules" if centre_read[k] >= 0.5 else
                    "read by the head reading, lost to the rules" if head_read[k] >= 0.5 else
                    "a head peak, no box at IoU 0.5" if found["head"][k] >= THRESHOLD else
                    "the centre map alone" if found["centre"][k] >= THRESHOLD else "neither map")
            kinds[kind] += 1
            if len(head_boxes):
                tops = np.column_stack([(head_boxes[:, 0] + head_boxes[:, 2]) / 2, head_boxes[:, 1]])
                distances = np.hypot(tops[:, 0] - middles[k], tops[:, 1] - truth[k, 1]) / heights[k]
                box = head_boxes[np.argmin(distances)]
                nearest[kind].append([distances.min(), box_iou(truth[k:k + 1], box[None])[0, 0],
                                      (box[3] - box[1]) / heights[k], (box[2] - box[0]) / (truth[k, 2] - truth[k, 0])])
    runtime.close()
    print(f"people overlapping another, {bundle}, frames {sys.argv[2]}: {sum(kinds.values())}")
    for kind, count in kinds.most_common():
        line = f"- {kind}: {count}"
        if nearest[kind]:
            medians = np.median(np.array(nearest[kind]), axis=0)
            line += (f"; the nearest head's person: {medians[0]:.2f} heights away, IoU {medians[1]:.2f}, "
                     f"{medians[2]:.2f}x as tall, {medians[3]:.2f}x as wide (medians)")
        print(line)


if __name__ == "__main__":
    main()
