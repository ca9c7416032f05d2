"""Real frames: a bundle whose r0 network has a head map and a size map beside today's centre map
(``train_both.py``, exported), on TUD-Stadtmitte's halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python measure_both.py ARM SEED BUNDLE -o results [--same-head D] [--iou T]

r0's heat maps are decoded twice: as shipped (its centre map) and from its head map, the centre being the head plus
the offset there times the size map's height; each head-found person whose box overlaps every one of today's by less
than IoU T (default 0.5) is added, and with ``--same-head D`` dropped after the seam rule where another reported
person's head lies within D of their height (``union.py``). The network runs once a frame.
"""

from __future__ import annotations

import sys

import numpy as np
import union
from train_both import HEAD_CHANNEL, SIZE_CHANNEL, SIZE_UNIT
from union import visible_decode

from vc.deploy.heatmaps import CENTRE_CHANNEL, CENTRE_OFFSET_CHANNELS

_ORIGINAL_PEOPLE = union.runtime.RegionRunner.people


def head_maps(heatmaps: np.ndarray) -> np.ndarray:
    """The heat maps as a head-anchored network's (``visible_decode`` with offsets and sizes in SIZE_UNIT cells):
    the head map in the centre map's place, and the offsets (in the person's heights) in SIZE_UNIT cells by the
    size map's height at each cell."""
    maps = heatmaps.copy()
    maps[CENTRE_CHANNEL] = heatmaps[HEAD_CHANNEL]
    maps[CENTRE_OFFSET_CHANNELS] *= np.exp(heatmaps[SIZE_CHANNEL])[None]  # x size / SIZE_UNIT
    return maps


def people(self, frame: np.ndarray):
    if self.entry.name != "r0":
        return _ORIGINAL_PEOPLE(self, frame)
    heatmaps = self.heatmaps(frame)
    today = self.faced(frame, self.people_in(heatmaps))
    with visible_decode.anchored():
        found = self.faced(frame, self.people_in(head_maps(heatmaps)))
    added = union.added_to(today, found)
    return today + added


if __name__ == "__main__":
    assert SIZE_UNIT == 20.0  # union.main installs visible_decode with 20-cell offsets and sizes
    sys.argv[4:4] = [sys.argv[3]]  # union's HEAD_BUNDLE: this one (its r0 graph is not run a second time)
    union._people = people
    union.main()
