"""Real people of a half, for the probes: the bundle's people (score >= 0.5) matched (IoU >= 0.5) to a
YOLO11n-pose @1280 person whose shoulders and hips say front or behind (the reference's own facing, as 0027 read it);
each cut as the runtime cuts them, with the bundle's own front logit. The crops are real people: they stay on the
machine that made them and are never committed (frozen, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-01-head-colours/probe/realset.py BUNDLE pets|tud FIRST LAST STEP OUT.npz
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import onnxruntime as ort
from common import DATA, REFERENCE, iou, reference_facing

from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.baselines import YoloPoseOnnx
from vc.model.facing import crop_graph


def main() -> None:
    bundle, camera, out = Path(sys.argv[1]), sys.argv[2], sys.argv[6]
    first, last, step = (int(value) for value in sys.argv[3:6])
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    session = ort.InferenceSession(crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    rows: dict[str, list] = {"crops": [], "front": [], "heights": [], "frames": [], "boxes": [], "logits": []}
    with Runtime(bundle, threads=2) as runtime:
        for frame in FrameSource(Path(DATA[camera][0]), FrameRange(first, last, step)):
            people = [p for p in runtime.run(frame.image).people if p.score >= 0.5 and not p.weak]
            found = reference(frame.image)
            for person in people:
                overlaps = [iou(person.box, box) for box in found.boxes]
                if not overlaps or max(overlaps) < 0.5:
                    continue
                facing = reference_facing(found.keypoints[int(np.argmax(overlaps))])
                if not facing or person.pair_handedness is None:
                    continue
                cut = session.run(None, {FRAME_INPUT: frame.image[None],
                                         ROIS_INPUT: crop_rois(np.asarray(person.box)[None])})[0]
                rows["crops"].append(np.clip(np.rint(cut[0].transpose(1, 2, 0) * 255), 0, 255).astype(np.uint8))
                handedness = float(np.mean(person.pair_handedness))  # -tanh(logit / 2), vc.deploy.facing step 3
                rows["logits"].append(-2.0 * float(np.arctanh(np.clip(handedness, -0.999999, 0.999999))))
                rows["front"].append(facing > 0)
                rows["heights"].append(person.box[3] - person.box[1])
                rows["frames"].append(frame.number)
                rows["boxes"].append(person.box)
    np.savez_compressed(out, **{name: np.array(values) for name, values in rows.items()})
    print(out, len(rows["front"]), "people, seen from the front:", round(float(np.mean(rows["front"])), 3))


if __name__ == "__main__":
    main()
