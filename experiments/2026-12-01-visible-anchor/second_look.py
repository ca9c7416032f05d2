"""Today's r0 network and a head-anchored one side by side: the people the head network finds that today's does not,
added to today's (frozen experiment, issue 57 item 2). An upper bound on what a head map beside today's centre map
could add, at twice r0's network time; not a design.

    PYTHONPATH=../.. python second_look.py ARM CONTROL_BUNDLE HEAD_BUNDLE -o results --offset-unit U [--iou T]
        [--size-unit U]

r0 of CONTROL_BUNDLE decodes as shipped (numpy decoder); r0 of HEAD_BUNDLE (``anchors.py train --anchor head``,
exported) runs on the same crop and decodes as :mod:`visible_decode` does; each of its people whose box overlaps every
one of today's by less than IoU T (default 0.5) is added. Measured as ``measure.py`` measures.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import visible_decode
from measure import _option, crowd_measure

import vc.deploy.runtime as runtime
from vc.deploy.boxes import box_iou
from vc.deploy.engines import graph_session

_ORIGINAL_PEOPLE = runtime.RegionRunner.people
_HEAD_GRAPHS: dict[int, object] = {}


def _people(self, frame: np.ndarray):
    people = _ORIGINAL_PEOPLE(self, frame)
    if self.entry.name != "r0":
        return people
    graph = _HEAD_GRAPHS.get(id(self))
    if graph is None:
        graph = _HEAD_GRAPHS[id(self)] = graph_session("onnxruntime", HEAD_MODEL[0].read_bytes(), 1)
    x0, y0, width, height = self.entry.crop_window
    heatmaps = graph(np.ascontiguousarray(frame[y0:y0 + height, x0:x0 + width])[None])[0]
    with visible_decode.anchored():
        found = self.faced(frame, self.people_in(heatmaps))
    boxes = np.array([person.box for person in people if not person.weak]).reshape(-1, 4)
    added = [person for person in found
             if not person.weak and (not len(boxes) or box_iou(person.box[None], boxes).max() < IOU[0])]
    return people + added


HEAD_MODEL: list[Path] = []
IOU = [0.5]

if __name__ == "__main__":
    unit, iou, size = _option("--offset-unit"), _option("--iou"), _option("--size-unit")
    visible_decode.install(set(), None, None if unit is None else float(unit), None if size is None else float(size))
    IOU[0] = 0.5 if iou is None else float(iou)
    arm, control, head = sys.argv[1:4]
    HEAD_MODEL.append(Path(head) / "models" / "r0.onnx")
    sys.argv[1:4] = [arm, control]
    runtime.RegionRunner.people = _people
    crowd_measure.main()
