"""Real frames: bundles whose r0 network peaks at people's visible centroid or head, decoded by
:mod:`visible_decode`, on TUD-Stadtmitte's halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python measure.py ARM B0 [B1 B2] -o results [--centre]
    PYTHONPATH=../.. python measure.py ARM B0 -o results [--separation S] [--offset-unit U] [--size-unit U]
        [--no-voted-people] [--seam-iou T] [--same-head D] [--size-agreement F]

As ``../2026-12-01-tud-denser-crowd/measure.py`` measures (its control is ``results/crowd_5`` there), with the numpy
decoder patched by :func:`visible_decode.install` for r0's heat maps (96 x 32 cells) unless ``--centre`` (today's
decoding: the arm's bundle decoded as shipped); ``--separation S``: anchors closer than S heights are one person's;
``--offset-unit U``: its offsets are in U cells; ``--size-unit U``: its size map's; ``--no-voted-people``: the
decoder's step 1b adds nobody; ``--seam-iou T``: one region's person gives way to another's above IoU T
(the runtime's 0.6); ``--same-head D``: r0's people whose head (box top middle) lies within D of another region's
person's height of theirs are dropped; ``--size-agreement F``: the decoder's box stays where its height is within F of
the size map's.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import visible_decode

import vc.deploy.runtime as runtime

_SPEC = importlib.util.spec_from_file_location(
    "crowd_measure", Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd" / "measure.py")
crowd_measure = sys.modules["crowd_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(crowd_measure)

def without_same_heads(people: list, reach: float) -> list:
    """``people`` without r0's whose box's top middle (the head) lies within ``reach`` of another region's person's
    height of that person's top middle: one head, one person, whichever region saw it."""
    others = [person for person in people if person.region != "r0" and not person.weak]
    if not others:
        return people
    tops = np.array([[(person.box[0] + person.box[2]) / 2, person.box[1]] for person in others])
    heights = np.array([person.box[3] - person.box[1] for person in others])
    kept = []
    for person in people:
        if person.region == "r0":
            top = np.array([(person.box[0] + person.box[2]) / 2, person.box[1]])
            if np.any(np.hypot(*(tops - top).T) < reach * heights):
                continue
        kept.append(person)
    return kept


def _option(name: str) -> str | None:
    """Take ``name VALUE`` out of the command line (the crowd experiment's parser does not know it)."""
    if name not in sys.argv:
        return None
    at = sys.argv.index(name)
    value = sys.argv[at + 1]
    del sys.argv[at:at + 2]
    return value


if __name__ == "__main__":
    separation, unit, size = _option("--separation"), _option("--offset-unit"), _option("--size-unit")
    seam_iou = _option("--seam-iou")
    if seam_iou is not None:
        _without = runtime.without_seam_duplicates
        runtime.without_seam_duplicates = lambda people: _without(people, float(seam_iou))
    same_head, agreement = _option("--same-head"), _option("--size-agreement")
    if same_head is not None:
        _seam_rule = runtime.without_seam_duplicates
        runtime.without_seam_duplicates = lambda people: without_same_heads(_seam_rule(people), float(same_head))
    voted_people = "--no-voted-people" not in sys.argv
    if not voted_people:
        sys.argv.remove("--no-voted-people")
    if "--centre" in sys.argv:
        sys.argv.remove("--centre")
    else:
        visible_decode.install({(32, 96)}, None if separation is None else float(separation),
                               None if unit is None else float(unit), None if size is None else float(size),
                               voted_people, None if agreement is None else float(agreement))
    crowd_measure.main()
