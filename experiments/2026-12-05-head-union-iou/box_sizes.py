"""The box sizes (box over truth) of the centre and head readings' people nearest each true person's head, for
people apart and people overlapping another, on TUD-Stadtmitte (frozen probe).

    PYTHONPATH=src python experiments/2026-12-05-head-union-iou/box_sizes.py BUNDLE FIRST:LAST

A reading's person stands for a true person when their head (box top middle) is within 0.1 of the person's height
of the true box's top middle.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import grouped
from vc.evaluation.mot import read_mot_boxes

DATA = Path("../shared/data/tud_stadtmitte")
REACH = 0.1


def main() -> None:
    truths = read_mot_boxes(DATA / "gt_world.txt")
    runtime = Runtime(Path(sys.argv[1]), threads=2)
    ratios: dict[tuple[str, str], list] = {(group, reading): [] for group in ("apart", "overlapping another")
                                           for reading in ("centre", "head")}
    for frame in FrameSource(DATA / "frames", FrameRange.parse(sys.argv[2])):
        truth = truths.get(frame.number, np.zeros((0, 4)))
        if not len(truth):
            continue
        boxes: dict[str, list] = {"centre": [], "head": []}
        for runner in runtime.runners:
            maps = runner.heatmaps(frame.image)
            for person in runner.decode(maps, runner.entry.decode, runner.entry.expected_height_px, None):
                if not person.weak:
                    box = runner.to_frame(np.asarray(person.box).reshape(2, 2)).reshape(4)
                    boxes["head" if person.head_found else "centre"].append(box)
        groups = np.where(grouped(truth), "overlapping another", "apart")
        for reading, found in boxes.items():
            found = np.array(found).reshape(-1, 4)
            if not len(found):
                continue
            tops = np.column_stack([(found[:, 0] + found[:, 2]) / 2, found[:, 1]])
            for (x0, y0, x1, y1), group in zip(truth, groups, strict=True):
                distances = np.hypot(tops[:, 0] - (x0 + x1) / 2, tops[:, 1] - y0) / (y1 - y0)
                box = found[np.argmin(distances)]
                if distances.min() < REACH:
                    ratios[group, reading].append([(box[3] - box[1]) / (y1 - y0), (box[2] - box[0]) / (x1 - x0)])
    runtime.close()
    for (group, reading), values in ratios.items():
        values = np.array(values)
        print(f"{group}, {reading} reading: {len(values)} people; height quartiles "
              f"{np.percentile(values[:, 0], [25, 50, 75]).round(2).tolist()}, width quartiles "
              f"{np.percentile(values[:, 1], [25, 50, 75]).round(2).tolist()}")


if __name__ == "__main__":
    main()
