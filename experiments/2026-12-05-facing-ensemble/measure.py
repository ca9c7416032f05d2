"""A bundle read with its facing model's outputs averaged with other facing models' (frozen experiment, issue 57
item 4): does a facing model averaged over several read real people's front and back better than one?

    PYTHONPATH=../../src python measure.py CAMERA SEED HALF BUNDLE [FACING.onnx ...] >> results/pose.jsonl

Without FACING models this is the bundle as shipped. Every output (the front logit, the face's turn, the head's
front logit) is the mean of the models' outputs, before the runtime's own steps (the mirror's reading, the head's
share for small people); with ``AVERAGED=front_logit,head_front_logit`` in the environment only those are, the
others the bundle's own model's. Read and scored as ``../2026-12-02-keypoint-model-capacity/measure.py`` reads and
scores.
"""

from __future__ import annotations

import importlib.util
import json
import os
import sys
from pathlib import Path

import numpy as np

from vc.deploy import facing
from vc.deploy.engines import onnxruntime_inference

_SPEC = importlib.util.spec_from_file_location(
    "capacity_measure", Path(__file__).parent.parent / "2026-12-02-keypoint-model-capacity" / "measure.py")
capacity = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(capacity)
ROOT = Path(__file__).parent.parent.parent
EXTRA: list[bytes] = []
_INIT = facing.FacingReader.__init__


def init_with_extra_models(self, model: bytes, threads: int = 1) -> None:
    _INIT(self, model, threads)
    self.extra = [onnxruntime_inference(extra, threads) for extra in EXTRA]


def averaged_outputs(self, parts) -> dict[str, np.ndarray]:
    parts = list(parts)
    sessions = [self.session, *self.extra]
    readings = [[session.run(self.outputs, {facing.FRAME_INPUT: part, facing.ROIS_INPUT: roi})
                 for part, roi in parts] for session in sessions]
    averaged = os.environ.get("AVERAGED")
    averaged = self.outputs if averaged is None else averaged.split(",")
    return {name: np.mean([np.asarray([reading[index] for reading in model], np.float32).reshape(-1)
                           for model in (readings if name in averaged else readings[:1])], axis=0).astype(np.float32)
            for index, name in enumerate(self.outputs)}


def main() -> None:
    camera, seed, which, bundle = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    EXTRA.extend(Path(path).read_bytes() for path in sys.argv[5:])
    facing.FacingReader.__init__, facing.FacingReader._outputs = init_with_extra_models, averaged_outputs
    first, last, step = capacity.CAMERAS[camera][3][which]
    os.chdir(ROOT)  # the capacity measure names the data relative to the repository
    result = capacity.half({"arm": bundle.resolve()}, camera, first, last, step)
    print(json.dumps({"seed": seed, "camera": camera, "bundle": str(bundle), "extra": sys.argv[5:],
                      "averaged": os.environ.get("AVERAGED", "all"), **result}),
          flush=True)


if __name__ == "__main__":
    main()
