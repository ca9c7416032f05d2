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
from pathlib import Path

import vc.deploy.decode as decode
import vc.deploy.native as native

HERE = Path(__file__).parent
_WIDTHS = importlib.util.spec_from_file_location("measure_widths", HERE / "measure_widths.py")
widths = sys.modules["measure_widths"] = importlib.util.module_from_spec(_WIDTHS)
_WIDTHS.loader.exec_module(widths)  # its per-thread flag of the head reading, and results-as-shipped's measure
_VOTE_CENTRES = decode._vote_centres


def vote_centres_not_for_heads(*args, **kwargs):
    if getattr(widths._reading, "heads", False):
        return {}, []
    return _VOTE_CENTRES(*args, **kwargs)


if __name__ == "__main__":
    decode._read, decode._vote_centres = widths.read_flagging_heads, vote_centres_not_for_heads
    native.decode_readings = decode.decode_readings
    widths.shipped_measure.RESULTS = HERE / "results" / "votes"
    widths.shipped_measure.main()
