"""``split`` on the decoder as main has it since 0060, with ``widths``' narrower boxes for the heads' people (frozen
experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_split_widths.py CAMERA BUNDLE --seed S

``split`` (a centre box holding two or more heads' people replaced by them) lost TUD-Stadtmitte's each frame by
0.04-0.05: the heads' boxes that replaced a merged box were too big to match anyone. Since 0060 they are as tall as
their keypoints where the size map agrees; here they are also as wide as their keypoints alone (``widths``).
Writes ``results/split-widths/CAMERA/seedS_HALF.json``; the control is ``results/agree-1.15``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import vc.deploy.decode as decode
import vc.deploy.native as native
import vc.deploy.runtime as runtime

HERE = Path(__file__).parent


def _module(name: str):
    spec = importlib.util.spec_from_file_location(name, HERE / f"{name}.py")
    module = sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


if __name__ == "__main__":
    split, widths = _module("measure_split"), _module("measure_widths")
    runtime.with_heads_added = split.with_merged_boxes_split
    decode._read, decode._boxes = widths.read_flagging_heads, widths.boxes_of_keypoints
    native.decode_readings = decode.decode_readings
    widths.shipped_measure.RESULTS = HERE / "results" / "split-widths"
    widths.shipped_measure.main()
