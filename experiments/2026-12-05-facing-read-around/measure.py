"""The facing model read on more crops of each tall person than the crop and its mirror: boxes drawn a little larger
and smaller, or moved a little, each with its mirror, their readings averaged (frozen experiment, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-05-facing-read-around/measure.py CAMERA SEED 0|1 BUNDLE \
        >> experiments/2026-12-05-facing-read-around/results/CAMERA.jsonl

Runs ``../2026-12-02-keypoint-model-capacity/measure.py``'s measurement (pose agreement with YOLO11n-pose @1280, each
frame on its own and tracked, times a ratio in one run) on the bundle as shipped and, in the same process, the same
bundle with its facing readers reading around each person (:data:`AROUND`).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.facing import MIRRORED_FROM_PX, FacingReader, FacingReading
from vc.deploy.runtime import Runtime

_CAPACITY = importlib.util.spec_from_file_location(
    "capacity", Path(__file__).parent.parent / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity = sys.modules["capacity"] = importlib.util.module_from_spec(_CAPACITY)
_CAPACITY.loader.exec_module(capacity)

#: Arm name -> the boxes read for each tall person, as (height scale, centre moved across, centre moved down in
#: heights); each is read as it is and mirrored, and every reading averaged.
AROUND = {
    "scales": ((1.0, 0.0, 0.0), (0.92, 0.0, 0.0), (1.08, 0.0, 0.0)),
    "moves": ((1.0, 0.0, 0.0), (1.0, -0.04, 0.0), (1.0, 0.04, 0.0), (1.0, 0.0, -0.04), (1.0, 0.0, 0.04)),
}


def _moved(boxes: np.ndarray, scale: float, across: float, down: float) -> np.ndarray:
    height = boxes[:, 3] - boxes[:, 1]
    centre_x = (boxes[:, 0] + boxes[:, 2]) / 2 + across * height
    centre_y = (boxes[:, 1] + boxes[:, 3]) / 2 + down * height
    half_width, half_height = (boxes[:, 2] - boxes[:, 0]) / 2 * scale, height / 2 * scale
    return np.stack([centre_x - half_width, centre_y - half_height, centre_x + half_width, centre_y + half_height], 1)


def read_around(reader: FacingReader, frame: np.ndarray, boxes: np.ndarray, boxes_read) -> FacingReading:
    """``FacingReader.read`` with each tall person's readings (as it is and mirrored) averaged over ``boxes_read``:
    those tall enough to be read twice in every box of ``boxes_read``."""
    shipped = FacingReader.read(reader, frame, boxes)
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    smallest = min(scale for scale, _, _ in boxes_read)
    tall = (boxes[:, 3] - boxes[:, 1]) * smallest >= MIRRORED_FROM_PX
    if not tall.any():
        return shipped
    logits, across = [shipped.front_logits[tall]], [shipped.across[tall]] if shipped.across is not None else None
    for scale, right, down in boxes_read[1:]:
        other = FacingReader.read(reader, frame, _moved(boxes[tall], scale, right, down))
        logits.append(other.front_logits)
        if across is not None:
            across.append(other.across)
    front = shipped.front_logits.copy()
    front[tall] = np.mean(logits, axis=0)
    turned = None
    if across is not None:
        turned = shipped.across.copy()
        turned[tall] = np.mean(across, axis=0)
    return FacingReading(front, turned)


def runtime_reading_around(path: Path, **options) -> Runtime:
    """``Runtime`` for ``BUNDLE#ARM`` paths: the bundle with its facing readers reading around each person."""
    bundle, _, arm = str(path).partition("#")
    runtime = Runtime(Path(bundle), **options)
    if arm:
        for runner in runtime.runners:
            if runner.facing is not None:
                reader = runner.facing
                reader.read = lambda frame, boxes, reader=reader: read_around(reader, frame, boxes, AROUND[arm])
    return runtime


def main() -> None:
    camera, seed, which, bundle = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    capacity.Runtime = runtime_reading_around
    bundles = {"shipped": Path(bundle), **{arm: Path(f"{bundle}#{arm}") for arm in AROUND}}
    first, last, step = capacity.CAMERAS[camera][3][which]
    print(json.dumps({"seed": seed, "camera": camera, "bundles": {k: str(v) for k, v in bundles.items()},
                      **capacity.half(bundles, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
