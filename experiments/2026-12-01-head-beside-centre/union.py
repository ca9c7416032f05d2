"""Today's r0 and the head network's people it lacks, one head one person (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python union.py ARM SEED CONTROL_BUNDLE HEAD_BUNDLE -o results [--same-head D] [--iou T]
        [--halves H ...]

As ``../2026-12-01-visible-anchor/second_look.py`` (r0 of CONTROL_BUNDLE decodes as shipped; r0 of HEAD_BUNDLE, a
head-anchored network with offsets and a size map in 20 cells, runs on the same crop and its people whose box
overlaps every one of today's r0 people by less than IoU T are added), and then, after the runtime's seam rule, an
added person whose head (box top middle) lies within D of a person's height of any other reported person's head is
dropped: one head, one person. Without ``--same-head`` no added person is dropped (``second_look.py``'s arm).
Writes ``results/ARM/seedSEED_HALF.json`` for each half asked (both by default) of TUD-Stadtmitte, as
``measure.py`` there measures.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent.parent / "2026-12-01-visible-anchor"))
import second_look  # noqa: E402
import visible_decode  # noqa: E402
from measure import crowd_measure  # noqa: E402

import vc.deploy.runtime as runtime  # noqa: E402
from vc.deploy.boxes import box_iou  # noqa: E402
from vc.deploy.engines import graph_session  # noqa: E402

_ADDED: list = []  # the people the head network added to this frame (held, so that no id is reused)


def _people(self, frame: np.ndarray):
    """r0: today's people and those of the head network that none of them boxes (IoU below second_look's)."""
    if self.entry.name != "r0":
        return second_look._ORIGINAL_PEOPLE(self, frame)
    today = second_look._ORIGINAL_PEOPLE(self, frame)
    graph = second_look._HEAD_GRAPHS.get(id(self))
    if graph is None:
        graph = second_look._HEAD_GRAPHS[id(self)] = graph_session(
            "onnxruntime", second_look.HEAD_MODEL[0].read_bytes(), 1)
    x0, y0, width, height = self.entry.crop_window
    heatmaps = graph(np.ascontiguousarray(frame[y0:y0 + height, x0:x0 + width])[None])[0]
    with visible_decode.anchored():
        found = self.faced(frame, self.people_in(heatmaps))
    return today + added_to(today, found)


def added_to(today: list, found: list) -> list:
    """The people of ``found`` whose box overlaps every one of ``today``'s by less than second_look's IoU; they are
    this frame's added people (:data:`_ADDED`)."""
    boxes = np.array([person.box for person in today if not person.weak]).reshape(-1, 4)
    added = [person for person in found
             if not person.weak and (not len(boxes) or box_iou(person.box[None], boxes).max() < second_look.IOU[0])]
    _ADDED.clear()
    _ADDED.extend(added)
    return added


def _head(person) -> np.ndarray:
    return np.array([(person.box[0] + person.box[2]) / 2, person.box[1]])


def without_added_same_heads(people: list, reach: float) -> list:
    """``people`` without the added ones whose head lies within ``reach`` of another's height of theirs."""
    kept = []
    for person in people:
        if any(person is added for added in _ADDED) and not person.weak:
            others = [other for other in people if other is not person and not other.weak]
            if any(np.hypot(*(_head(other) - _head(person))) < reach * (other.box[3] - other.box[1])
                   for other in others):
                continue
        kept.append(person)
    return kept


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm")
    parser.add_argument("seed", type=int)
    parser.add_argument("control", type=Path)
    parser.add_argument("head", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--same-head", type=float)
    parser.add_argument("--iou", type=float, default=0.5)
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    visible_decode.install(set(), None, 20.0, 20.0)
    second_look.IOU[0] = args.iou
    second_look.HEAD_MODEL.append(args.head / "models" / "r0.onnx")
    runtime.RegionRunner.people = _people
    if args.same_head is not None:
        seam_rule = runtime.without_seam_duplicates
        runtime.without_seam_duplicates = lambda people: without_added_same_heads(seam_rule(people), args.same_head)
    # the crowd experiment's loop, its bundle for seed S being the control
    sys.argv[1:] = [args.arm, *[str(args.control)] * (args.seed + 1), "-o", str(args.out), "--seeds", str(args.seed),
                    "--halves", *args.halves]
    crowd_measure.main()


if __name__ == "__main__":
    main()
