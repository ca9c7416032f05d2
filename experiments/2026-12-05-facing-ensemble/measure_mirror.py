"""A bundle whose tall people's mirrored crop is read by a second facing model, not by its own (frozen experiment,
issue 57 item 4): the members' mean at no more cost than today's mirrored reading.

    PYTHONPATH=../../src python measure_mirror.py CAMERA SEED HALF BUNDLE FACING.onnx >> results/mirror_CAMERA.jsonl

People :data:`vc.deploy.facing.MIRRORED_FROM_PX` and taller are read twice as shipped, their crop and its mirror,
and the two readings averaged; here the mirror is read by FACING (a member trained with another seed on the same
renders, ``train_more.py``). Read and scored as ``measure.py``.
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

_SPEC = importlib.util.spec_from_file_location("ensemble_measure", Path(__file__).parent / "measure.py")
ensemble = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(ensemble)


def init_with_mirror_model(self, model: bytes, threads: int = 1) -> None:
    ensemble._INIT(self, model, threads)
    self.mirror = facing.FacingReader.__new__(facing.FacingReader)
    self.mirror.session = onnxruntime_inference(ensemble.EXTRA[0], threads)
    self.mirror.outputs = self.outputs


def read_mirror_by_the_second(self, frame, boxes) -> facing.FacingReading:
    """``FacingReader.read`` with the mirrored crops read by the second model (``self.mirror``)."""
    if not len(boxes):
        return _READ(self, frame, boxes)
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    heights = boxes[:, 3] - boxes[:, 1]
    rois = facing.crop_rois(boxes)
    found = self._outputs(facing.own_parts(frame, rois))
    tall = heights >= facing.MIRRORED_FROM_PX
    if tall.any():
        seen = self.mirror._outputs(facing.own_parts(frame, rois[tall], mirror=True))
        if self.reads_across:
            seen[facing.ACROSS_OUTPUT] = -seen[facing.ACROSS_OUTPUT]
        for name in self.outputs:
            found[name][tall] = (found[name][tall] + seen[name]) / 2.0
    return facing.FacingReading(facing.front_logits(found[facing.OUTPUT_NAME], found.get(facing.HEAD_OUTPUT), heights),
                                found[facing.ACROSS_OUTPUT] if self.reads_across else None)


_READ = facing.FacingReader.read


def main() -> None:
    camera, seed, which, bundle = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    ensemble.EXTRA.append(Path(sys.argv[5]).read_bytes())
    facing.FacingReader.__init__, facing.FacingReader.read = init_with_mirror_model, read_mirror_by_the_second
    first, last, step = ensemble.capacity.CAMERAS[camera][3][which]
    os.chdir(ensemble.ROOT)
    result = ensemble.capacity.half({"arm": bundle.resolve()}, camera, first, last, step)
    print(json.dumps({"seed": seed, "camera": camera, "bundle": str(bundle), "mirror": sys.argv[5], **result}),
          flush=True)


if __name__ == "__main__":
    main()
