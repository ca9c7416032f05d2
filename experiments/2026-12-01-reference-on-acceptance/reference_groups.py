"""What the reference detector, YOLO11n-pose @1280, reaches on issue 57's acceptance figures, on both halves of a
camera, scored by the miss analysis ``vc-eval`` gives a bundle (frozen experiment, issue 57).

    PYTHONPATH=../.. python reference_groups.py CAMERA BUNDLE -o results/CAMERA.json

CAMERA is ``pets`` or ``tud`` (halves as :mod:`benchmarks.protocol` defines them). The bundle only carries the
evaluation (any bundle of the camera: its own detections are scored beside and not reported). YOLO's detections,
each frame on its own, are analysed at their own operating point, as the bundle's are.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path
from unittest import mock

import vc.evaluation.real_video as real_video
from vc.deploy.frames import FrameRange
from vc.evaluation.annotated_area import AnnotatedArea
from vc.evaluation.misses import analyse_misses
from vc.evaluation.mot import read_mot_boxes
from vc.evaluation.real_video import EvaluationRequest, ExternalModel, evaluate_bundle

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"
YOLO = DATA.parent / "baselines" / "yolo11n-pose-1280.onnx"
NAME = "YOLO11n-pose@1280"
CAMERAS = {
    "pets": {"video": DATA / "pets09_s2l1" / "vtest.avi", "gt": DATA / "pets09_s2l1" / "gt_dev_frames_0001-0400.txt",
             "frame_size": (768, 576), "fps": None, "halves": {"choosing": "1:200:5", "confirming": "201:400:5"}},
    "tud": {"video": DATA / "tud_stadtmitte" / "frames", "gt": DATA / "tud_stadtmitte" / "gt_world.txt",
            "frame_size": (640, 480), "fps": 25.0, "halves": {"choosing": "1:90", "confirming": "91:179"}},
}


def reference_on(camera: dict, half: str, bundle: Path) -> dict:
    """The reference's AP50 and miss analysis on one half of ``camera``."""
    selection = FrameRange.parse(camera["halves"][half])
    with tempfile.TemporaryDirectory() as scratch, \
            mock.patch.object(real_video, "_pose_agreements", wraps=real_video._pose_agreements) as agreements:
        request = EvaluationRequest(bundle=bundle, video=camera["video"], ground_truth=camera["gt"],
                                    output=Path(scratch), frames=selection, hog=False, threads=2,
                                    externals=(ExternalModel(YOLO, NAME),), fps=camera["fps"])
        report = evaluate_bundle(request, show_progress=False)
    images = agreements.call_args.args[0][NAME].images  # every detector's per-frame results, as vc-eval holds them
    misses = analyse_misses(images, list(range(selection.first, selection.last + 1, selection.step)), None,
                            AnnotatedArea.of(read_mot_boxes(camera["gt"])), camera["frame_size"])
    return {"frames": camera["halves"][half], "ap50": report.metrics["detectors"][NAME]["ap50"],
            "recall_by_group": misses.recall_by_group(), "recall_by_height": misses.recall_by_height(),
            "recall_by_edge": misses.recall_by_edge(), "recall": misses.recall, "precision": misses.precision}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=tuple(CAMERAS))
    parser.add_argument("bundle", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    results = {half: reference_on(CAMERAS[args.camera], half, args.bundle) for half in CAMERAS[args.camera]["halves"]}
    for half, figures in results.items():
        print(half, json.dumps(figures))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
