"""Each compile's bundle as shipped (control) against the same bundle whose facing model also reads front from behind
by the head's colours, for people under the runtime's gate (the arm: vc-train's facing model since decision 0041,
trained on the compile's renders with its seed; its classifier and face turn are bit for bit the control's). Both
are read in one pass over a half, each frame on its own and tracked as vc-eval tracks, and scored against
YOLO11n-pose @1280 as vc-eval scores pose (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-12-01-head-colours/arms.py CONTROL_BUNDLE RENDERS SEED CAMERA WORK \
        [CLASSIFIER_WEIGHT [HALF]] >> experiments/2026-12-01-head-colours/results/arms.jsonl

CLASSIFIER_WEIGHT: the classifier's share beside the head's (vc.deploy.facing.CLASSIFIER_WEIGHT_BELOW) for this
run; HALF: 0 (choosing) or 1 (confirming), both by default. WORK keeps the arm's run and bundle; one JSON line per
half.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import vc.deploy.facing as facing
from vc.deploy.bundle import load_bundle
from vc.deploy.facing import FacingReader

# The face turn's arms (frozen): the arm bundle is the control with the facing model vc-train trains today, and
# both are read in one pass as vc-eval reads them; only the question differs.
_FACE_TURN = Path(__file__).resolve().parent.parent / "2026-12-01-face-turn" / "arms.py"
_SPEC = importlib.util.spec_from_file_location("face_turn_arms", _FACE_TURN)
face_turn_arms = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(face_turn_arms)


def main() -> None:
    control, renders, seed, camera, work = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4], \
        Path(sys.argv[5])
    if len(sys.argv) > 6:
        facing.CLASSIFIER_WEIGHT_BELOW = float(sys.argv[6])
    halves = face_turn_arms.DATA[camera][3]
    if len(sys.argv) > 7:
        halves = [halves[int(sys.argv[7])]]
    arm, report = face_turn_arms.arm_bundle(control, renders, seed, work)
    assert FacingReader(load_bundle(arm).facing).reads_head
    for first, last, step in halves:
        row = face_turn_arms.half({"control": control, "head colours": arm}, camera, first, last, step)
        print(json.dumps({"control": str(control), "seed": seed, "camera": camera,
                          "classifier_weight_below": facing.CLASSIFIER_WEIGHT_BELOW,
                          "head_colours": report.get("head_colours"), **row}), flush=True)


if __name__ == "__main__":
    main()
