"""Real frames: bundles whose r0 network peaks at people's visible centroid or head, decoded by
:mod:`visible_decode`, on TUD-Stadtmitte's halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python measure.py ARM B0 [B1 B2] -o results [--centre]
    PYTHONPATH=../.. python measure.py ARM B0 -o results [--separation S] [--offset-unit U] [--size-unit U]
        [--no-voted-people] [--seam-iou T]

As ``../2026-12-01-tud-denser-crowd/measure.py`` measures (its control is ``results/crowd_5`` there), with the numpy
decoder patched by :func:`visible_decode.install` for r0's heat maps (96 x 32 cells) unless ``--centre`` (today's
decoding: the arm's bundle decoded as shipped); ``--separation S``: anchors closer than S heights are one person's;
``--offset-unit U``: its offsets are in U cells; ``--size-unit U``: its size map's; ``--no-voted-people``: the
decoder's step 1b adds nobody; ``--seam-iou T``: one region's person gives way to another's above IoU T
(the runtime's 0.6).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import visible_decode

import vc.deploy.runtime as runtime

_SPEC = importlib.util.spec_from_file_location(
    "crowd_measure", Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd" / "measure.py")
crowd_measure = sys.modules["crowd_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(crowd_measure)

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
    voted_people = "--no-voted-people" not in sys.argv
    if not voted_people:
        sys.argv.remove("--no-voted-people")
    if "--centre" in sys.argv:
        sys.argv.remove("--centre")
    else:
        visible_decode.install({(32, 96)}, None if separation is None else float(separation),
                               None if unit is None else float(unit), None if size is None else float(size),
                               voted_people)
    crowd_measure.main()
