"""The facing model (vc.model.facing: the classifier, the face turn and the head's colours) trained on a compile's
renders with its seed as vc-train trains it, but with the classifier trained for EPOCHS epochs (shipped: 8), in a
copy of a bundle (frozen experiment, issue 57 item 4).

    PYTHONPATH=src python experiments/2026-12-02-facing-trained-longer/train_arm.py RENDERS SEED BUNDLE EPOCHS WORK \
        >> experiments/2026-12-02-facing-trained-longer/results/training.jsonl

WORK receives run/ (facing.onnx, facing.json) and bundle/ (BUNDLE with this facing model in place of its own).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

from vc.model.export import export_facing, with_facing
from vc.model.facing import (
    FACING_MODEL,
    FACING_REPORT,
    dataset_crops,
    train_face_turn,
    train_facing,
    train_head_colours,
)

_SPEC = importlib.util.spec_from_file_location(
    "keypoint_arm", Path(__file__).parents[1] / "2026-12-02-keypoint-model-capacity" / "train_arm.py")
KEYPOINT_ARM = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(KEYPOINT_ARM)


def main() -> None:
    renders, seed, control = Path(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3])
    epochs, work = int(sys.argv[4]), Path(sys.argv[5])
    run, out = work / "run", work / "bundle"
    run.mkdir(parents=True, exist_ok=True)
    train, held_out = dataset_crops(renders)
    result = train_facing(train.facing, held_out.facing, seed, epochs=epochs, show_progress=False)
    head = train_head_colours(train.facing, held_out.facing, seed)
    turn = train_face_turn(train.turn, held_out.turn, seed, show_progress=False)
    (run / FACING_MODEL).write_bytes(export_facing(result.net, turn.net, head.net))
    report = {**result.to_dict(), "face_turn": turn.to_dict(), "head_colours": head.to_dict()}
    (run / FACING_REPORT).write_text(json.dumps(report, indent=1))
    KEYPOINT_ARM.bundle_with(control, run, with_facing, out)
    print(json.dumps({"renders": str(renders), "seed": seed, "epochs": epochs, "work": str(work),
                      "held_out_accuracy": report.get("held_out_accuracy"), "seconds": report.get("seconds")}),
          flush=True)


if __name__ == "__main__":
    main()
