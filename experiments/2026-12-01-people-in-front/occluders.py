"""Who stands in front of TUD-Stadtmitte's far-band people that overlap another (frozen; decision 0033).

    PYTHONPATH=../.. python occluders.py BUNDLE [--frames 1:90]

For each annotated person whose foot point lies on the bundle's first region's ground (r0, the far band) and whose
box overlaps another's by IoU >= 0.1, the overlapping neighbour nearest the camera (the lowest box bottom): how far
(m) its foot point lies outside r0's ground polygon, against the 1.5 m border ring that renders place people in.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from shapely.geometry import Point, Polygon

from vc.deploy.boxes import box_iou
from vc.evaluation.metrics import GROUP_IOU, grouped
from vc.render.placement import BORDER_RING_M

GROUND_TRUTH = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "tud_stadtmitte" / "gt_world.txt"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--frames", default="1:90")
    args = parser.parse_args()
    manifest = json.loads((args.bundle / "manifest.json").read_text())
    far_band = Polygon(manifest["regions"][0]["ground_polygon"]["coordinates"][0])
    first, last = map(int, args.frames.split(":"))
    rows = np.loadtxt(GROUND_TRUTH, delimiter=",")
    people = 0
    distances = []
    for frame in range(first, last + 1):
        annotated = rows[rows[:, 0] == frame]
        boxes = np.c_[annotated[:, 2:4], annotated[:, 2:4] + annotated[:, 4:6]]
        overlaps = box_iou(boxes, boxes)
        np.fill_diagonal(overlaps, 0.0)
        for person in np.flatnonzero(grouped(boxes)):
            if not far_band.contains(Point(annotated[person, 7], annotated[person, 8])):
                continue
            people += 1
            in_front = [other for other in np.flatnonzero(overlaps[person] >= GROUP_IOU)
                        if boxes[other, 3] > boxes[person, 3]]
            if in_front:
                nearest = max(in_front, key=lambda other: boxes[other, 3])
                distances.append(far_band.distance(Point(annotated[nearest, 7], annotated[nearest, 8])))
    distances = np.array(distances)
    print(f"frames {args.frames}: {people} far-band people overlapping another, {len(distances)} with an overlapping "
          f"neighbour nearer the camera")
    print(f"  that neighbour's distance outside the far band (m), 10/25/50/75/90 %: "
          f"{np.percentile(distances, [10, 25, 50, 75, 90]).round(2).tolist()}")
    print(f"  within the {BORDER_RING_M} m border ring: {np.mean(distances <= BORDER_RING_M):.3f}; "
          f"on the far band itself: {np.mean(distances == 0):.3f}")


if __name__ == "__main__":
    main()
