"""Pose agreement with YOLO11n-pose @1280 of today's bundle and the behind bundle, read in one process frame by frame
(``../2026-12-02-keypoint-model-capacity/measure.py``'s ``half``), the people behind added at score T (frozen
experiment, issue 57 item 2).

    PYTHONPATH=src python experiments/2026-12-03-second-person/pose.py CAMERA 0|1 T NAME=BUNDLE ... \
        >> results/pose.jsonl

Both bundles are decoded by the numpy decoder (:func:`real.install`); only the behind layout's maps add people.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import real
import second_person

_SPEC = importlib.util.spec_from_file_location(
    "capacity_measure", Path(__file__).parent.parent / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity_measure = sys.modules["capacity_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(capacity_measure)


def main() -> None:
    camera, which, threshold = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    bundles = dict(argument.split("=", 1) for argument in sys.argv[4:])
    real.install()
    second_person.THRESHOLD[0] = threshold
    first, last, step = capacity_measure.CAMERAS[camera][3][which]
    print(json.dumps({"camera": camera, "threshold": threshold, "bundles": bundles,
                      **capacity_measure.half({name: Path(path) for name, path in bundles.items()}, camera, first,
                                              last, step)}), flush=True)


if __name__ == "__main__":
    main()
