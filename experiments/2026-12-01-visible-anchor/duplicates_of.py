"""Where a bundle's duplicate boxes come from: pairs of reported people, one frame at a time, whose boxes overlap at
IoU >= 0.5, by the regions that reported them (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python duplicates_of.py BUNDLE [--offset-unit U --size-unit U]   # TUD-Stadtmitte 1-90

With the units, r0 decodes as :mod:`visible_decode` does (a head-anchored r0). Pairs within one region are also
counted by how far apart their heads (nose, eyes, ears) are, in the taller one's box heights.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np
import visible_decode
from measure import crowd_measure

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime

DUPLICATE_IOU = 0.5


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--offset-unit", type=float)
    parser.add_argument("--size-unit", type=float)
    args = parser.parse_args()
    shapes = {(32, 96)} if args.offset_unit is not None else set()
    visible_decode.install(shapes, None, args.offset_unit, args.size_unit)
    tud = crowd_measure.TUD
    pairs: Counter[str] = Counter()
    head_gaps: list[float] = []
    people = 0
    with Runtime(args.bundle, threads=2) as runtime:
        for frame in FrameSource(tud["video"], FrameRange.parse(tud["halves"]["choosing"])):
            found = [person for person in runtime.run(frame.image).people if not person.weak]
            people += len(found)
            if len(found) < 2:
                continue
            boxes = np.array([person.box for person in found])
            overlap = np.triu(box_iou(boxes, boxes), 1)
            for first, second in zip(*np.nonzero(overlap >= DUPLICATE_IOU), strict=True):
                regions = "-".join(sorted((found[first].region, found[second].region)))
                pairs[regions] += 1
                if found[first].region == found[second].region:
                    heads = [person.keypoints[:5, :2].mean(axis=0) for person in (found[first], found[second])]
                    tall = max(boxes[first, 3] - boxes[first, 1], boxes[second, 3] - boxes[second, 1])
                    head_gaps.append(float(np.hypot(*(heads[0] - heads[1])) / tall))
    gaps = np.array(head_gaps)
    print(f"{args.bundle}: {people} people reported on frames 1-90; pairs at IoU >= {DUPLICATE_IOU}: {dict(pairs)}")
    if len(gaps):
        print(f"  within a region, heads apart (box heights) 10/25/50/75 %: "
              f"{np.percentile(gaps, [10, 25, 50, 75]).round(3).tolist()}")


if __name__ == "__main__":
    main()
