"""YOLO11n-pose @1280's recall of TUD-Stadtmitte's people overlapping another, on each half, by the miss analysis
``vc-eval`` gives the bundle (frozen experiment, issue 57 item 2): what a general detector trained on real people
finds of the people the issue asks for.

    PYTHONPATH=../.. python yolo_groups.py BUNDLE -o results/yolo_groups.json

The bundle only carries the evaluation (its own detections are scored beside); YOLO's detections, taken each frame on
its own, are analysed at their own operating point, as the bundle's are.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import vc.evaluation.real_video as real_video
from vc.deploy.frames import FrameRange
from vc.evaluation.annotated_area import AnnotatedArea
from vc.evaluation.misses import analyse_misses
from vc.evaluation.mot import read_mot_boxes
from vc.evaluation.real_video import EvaluationRequest, ExternalModel, evaluate_bundle

sys.path.insert(0, str(Path(__file__).parent))
from measure import crowd_measure  # noqa: E402  (the halves and camera of the crowd experiment)

YOLO = Path(__file__).resolve().parents[3] / "shared" / "baselines" / "yolo11n-pose-1280.onnx"
NAME = "YOLO11n-pose@1280"
FRAME_SIZE = (640, 480)  # TUD-Stadtmitte's frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    tud = crowd_measure.TUD
    captured = {}
    original = real_video._pose_agreements

    def keep_records(records, names):
        captured["records"] = records
        return original(records, names)

    real_video._pose_agreements = keep_records
    truth = read_mot_boxes(tud["gt"])
    results = {}
    for half, frames in tud["halves"].items():
        selection = FrameRange.parse(frames)
        with tempfile.TemporaryDirectory() as scratch:
            request = EvaluationRequest(bundle=args.bundle, video=tud["video"], ground_truth=tud["gt"],
                                        output=Path(scratch), frames=selection, hog=False, threads=2,
                                        externals=(ExternalModel(YOLO, NAME),), fps=tud["fps"])
            report = evaluate_bundle(request, show_progress=False)
        scored = list(range(selection.first, selection.last + 1, selection.step))
        misses = analyse_misses(captured["records"][NAME].images, scored, None, AnnotatedArea.of(truth), FRAME_SIZE)
        results[half] = {"frames": frames, "ap50": report.metrics["detectors"][NAME]["ap50"],
                         "recall_by_group": misses.recall_by_group(), "recall_by_height": misses.recall_by_height(),
                         "recall": misses.recall, "precision": misses.precision}
        print(half, results[half], flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
