"""The head-map bundles read by the decoder as main has it since 0060, with the head reading's people neither moved
nor added by the mask cells' votes (step 1b) (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_votes.py CAMERA BUNDLE --seed S

Step 1b moves a centre peak that few pixels vote for to where the votes put a person, and adds people where
unclaimed votes gather. Run on the heads, it can move a head's person onto the votes of the person in front, whose
centre the centre reading already has: a duplicate the union then drops. Heads stand apart; here the head
reading's people stay where their heads put them, and the votes add no one to that reading. Decoded by the numpy
decoder; the state that tells the head reading is per thread (the regions decode in threads of their own). Writes
``results/votes/CAMERA/seedS_HALF.json``; the control is ``results/agree-1.15``.
"""

from __future__ import annotations

import importlib.util
import sys
import threading
from pathlib import Path

import vc.deploy.decode as decode
import vc.deploy.native as native

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)
_READ, _VOTE_CENTRES = decode._read, decode._vote_centres
_reading = threading.local()  # .heads: whether this thread reads the heads


def read_flagging_heads(*args, from_heads: bool, **kwargs):
    _reading.heads = from_heads
    try:
        return _READ(*args, from_heads=from_heads, **kwargs)
    finally:
        _reading.heads = False


def vote_centres_not_for_heads(*args, **kwargs):
    if getattr(_reading, "heads", False):
        return {}, []
    return _VOTE_CENTRES(*args, **kwargs)


if __name__ == "__main__":
    decode._read, decode._vote_centres = read_flagging_heads, vote_centres_not_for_heads
    native.decode_readings = decode.decode_readings
    shipped_measure.RESULTS = Path(__file__).parent / "results" / "votes"
    shipped_measure.main()
