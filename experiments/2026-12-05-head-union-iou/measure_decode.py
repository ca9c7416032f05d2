"""The head-map bundles read by the decoder as main has it since 0060, with one of every region's decoder settings
(``DecodeConfig``, 0003) set otherwise (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure_decode.py FIELD=VALUE CAMERA BUNDLE --seed S

0003 chose the decoder's settings before the head map. Two bear on people in groups: ``reach_sideways`` (how far
from a person's centre their mask cells and keypoints shape the box: the heads' people in groups are read 1.8x as
wide as they are) and ``vote_support`` (the share of a person's pixels whose unclaimed votes add a person half
hidden behind another). Writes ``results/FIELD-VALUE/CAMERA/seedS_HALF.json``; the control is
``results/agree-1.15``.
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import replace
from pathlib import Path

import vc.deploy.runtime as runtime

_SHIPPED = importlib.util.spec_from_file_location(
    "shipped_measure", Path(__file__).parent.parent / "2026-12-05-results-as-shipped" / "measure.py")
shipped_measure = sys.modules["shipped_measure"] = importlib.util.module_from_spec(_SHIPPED)
_SHIPPED.loader.exec_module(shipped_measure)
_RUNNER_INIT = runtime.RegionRunner.__init__


def with_setting(field: str, value: float):
    def init(self, entry, *args, **kwargs):
        _RUNNER_INIT(self, replace(entry, decode=replace(entry.decode, **{field: value})), *args, **kwargs)
    return init


if __name__ == "__main__":
    field, value = sys.argv.pop(1).split("=")
    runtime.RegionRunner.__init__ = with_setting(field, float(value))
    shipped_measure.RESULTS = Path(__file__).parent / "results" / f"{field}-{value}"
    shipped_measure.main()
