"""``vc-eval``: a bundle on real video frames against ground-truth boxes, beside detectors trained on real photos.

    vc-eval BUNDLE --video V --gt GT.txt -o OUT [--frames first:last:step] [--no-hog] [--hog-upscale F]
            [--external MODEL.onnx [--external-size S] [--external-name NAME]] [--threads N] [--quiet]

For every selected frame each detector runs and is timed: the bundle (through :mod:`vc.deploy.runtime`, as the
appliance runs it), OpenCV's HOG people detector, and optionally any YOLO-pose style ONNX model. Writes
``OUT/metrics.json`` (AP50, milliseconds per frame, and for the bundle its operating point and recall by person
height), ``OUT/precision_recall.png``, ``OUT/contact_sheet.png`` (frames with the bundle's people in colour and
the ground truth in white) and ``OUT/detections.jsonl``. GT is in the MOT text format; only frames inside its
annotated range can be selected (a frame without a line there has nobody in it). Bad input exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from vc import __version__
from vc.baselines import HogPeopleDetector, YoloPoseOnnx
from vc.cli.common import handles_input_errors, positive_int
from vc.deploy.metrics import Evaluation, ImageResult, box_iou, evaluate
from vc.deploy.runtime import Person, Runtime
from vc.draw import contact_sheet, draw_people
from vc.errors import InputError
from vc.frames import FrameRange, FrameSource
from vc.io import atomic_directory, write_image, write_json
from vc.mot import read_mot_boxes
from vc.plots import plot_precision_recall

OURS = "visual compiler"
#: Ground-truth person heights (px) over which the bundle's recall is broken down.
HEIGHT_BINS = (0, 60, 80, 100, 10_000)
SHEET_FRAMES = 8
#: Ground-truth people overlapping another this much count as "in a group" in the breakdown.
GROUP_IOU = 0.1


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-eval", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("bundle", type=Path, help="a vc-export bundle (folder or zip)")
    parser.add_argument("--video", type=Path, required=True, help="video file or folder of frames")
    parser.add_argument("--gt", type=Path, required=True, help="ground-truth boxes, MOT text format")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    parser.add_argument("--frames", type=FrameRange.parse, default=None,
                        help="first:last:step, 1-based and inclusive (default: every annotated frame)")
    parser.add_argument("--no-hog", action="store_true", help="skip the HOG baseline (about 1 s per frame)")
    parser.add_argument("--hog-upscale", type=float, default=2.0, help="HOG runs on the frame upscaled this much")
    parser.add_argument("--external", type=Path, help="a YOLO-pose style ONNX model to compare with")
    parser.add_argument("--external-size", type=positive_int, help="its square input size (if dynamic)")
    parser.add_argument("--external-name", default=None, help="its label (default: the file name)")
    parser.add_argument("--threads", type=positive_int, default=None, help="threads per detector (default: all)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


@dataclass
class _Record:
    """One detector's results and timings over the frames."""

    images: list[ImageResult] = field(default_factory=list)
    milliseconds: list[float] = field(default_factory=list)

    def add(self, truth: np.ndarray, boxes: np.ndarray, scores: np.ndarray, seconds: float) -> None:
        self.images.append(ImageResult(truth_boxes=truth, boxes=np.asarray(boxes).reshape(-1, 4),
                                       scores=np.asarray(scores, np.float64).ravel()))
        self.milliseconds.append(seconds * 1e3)

    def summary(self, evaluation: Evaluation) -> dict:
        return {"ap50": round(evaluation.ap50, 4), "ground_truth": evaluation.ground_truth,
                "detections": int(len(evaluation.scores)),
                "ms_per_frame": {"median": round(float(np.median(self.milliseconds)), 2),
                                 "mean": round(float(np.mean(self.milliseconds)), 2)}}


def operating_point(images: list[ImageResult], evaluation: Evaluation) -> dict:
    """The score threshold of best F1, and what it finds and misses there, by ground-truth person height."""
    if not len(evaluation.scores):
        return {}
    f1 = 2 * evaluation.precision * evaluation.recall / np.maximum(evaluation.precision + evaluation.recall, 1e-9)
    best = int(np.argmax(f1))
    threshold = float(evaluation.scores[best])
    kept = [ImageResult(image.truth_boxes, image.boxes[image.scores >= threshold],
                        image.scores[image.scores >= threshold]) for image in images]
    matches = evaluate(kept).matches
    heights = np.concatenate([image.truth_boxes[:, 3] - image.truth_boxes[:, 1] for image in images])
    found = np.concatenate([np.isin(np.arange(len(image.truth_boxes)), [t for t, _ in pairs])
                            for image, pairs in zip(images, matches, strict=True)])
    by_height = {}
    for low, high in zip(HEIGHT_BINS[:-1], HEIGHT_BINS[1:], strict=True):
        inside = (heights >= low) & (heights < high)
        if inside.any():
            label = f"{low}-{high} px" if high < HEIGHT_BINS[-1] else f">= {low} px"
            by_height[label] = {"people": int(inside.sum()), "recall": round(float(found[inside].mean()), 4)}
    overlapped = np.concatenate([_overlapped(image.truth_boxes) for image in images])
    by_overlap = {label: {"people": int(inside.sum()), "recall": round(float(found[inside].mean()), 4)}
                  for label, inside in (("apart", ~overlapped), ("overlapping another", overlapped)) if inside.any()}
    detections = sum(len(image.boxes) for image in kept)
    return {"score_threshold": round(threshold, 4), "precision": round(float(evaluation.precision[best]), 4),
            "recall": round(float(evaluation.recall[best]), 4), "f1": round(float(f1[best]), 4),
            "false_positives": int(detections - found.sum()), "missed": int((~found).sum()),
            "recall_by_height": by_height, "recall_by_overlap": by_overlap}


def _overlapped(boxes: np.ndarray) -> np.ndarray:
    """Which ground-truth people overlap another by IoU >= :data:`GROUP_IOU` (groups, partial occlusion)."""
    iou = box_iou(boxes, boxes)
    np.fill_diagonal(iou, 0.0)
    return iou.max(axis=1, initial=0.0) >= GROUP_IOU


def _detectors(args: argparse.Namespace) -> dict:
    detectors = {}
    if not args.no_hog:
        detectors["HOG (OpenCV, real photos)"] = HogPeopleDetector(args.hog_upscale)
    if args.external:
        model = YoloPoseOnnx(args.external, args.external_size, args.threads)
        detectors[args.external_name or f"{args.external.name} @{model.size}"] = model
    return detectors


def _check_selection(source: FrameSource, truth: dict[int, np.ndarray], gt_path: Path) -> None:
    last_annotated = max(truth)
    beyond = source.frames.last is None or source.frames.last > last_annotated
    if beyond and source.count > source.frames.count(last_annotated):
        raise InputError(gt_path, "frames", f"the selection reaches past the last annotated frame "
                                            f"({last_annotated}); select with --frames first:{last_annotated}:step")


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    truth = read_mot_boxes(args.gt)
    runtime = Runtime(args.bundle, threads=args.threads)
    args.frames = args.frames or FrameRange(1, max(truth))
    source = FrameSource(args.video, args.frames)
    _check_selection(source, truth, args.gt)
    if args.threads:
        cv2.setNumThreads(args.threads)
    others = _detectors(args)
    records = {OURS: _Record(), **{name: _Record() for name in others}}
    sheet_numbers = set(np.linspace(0, source.count - 1, min(SHEET_FRAMES, source.count)).round().astype(int))
    sheet, lines = [], []
    width, height = runtime.bundle.frame_size
    for index, frame in enumerate(tqdm(source, total=len(source), desc="vc-eval", unit="frame",
                                       disable=args.quiet)):
        if frame.image.shape != (height, width, 3):
            raise InputError(args.video, f"frame {frame.number}", f"is {frame.image.shape[1]}x"
                                                                  f"{frame.image.shape[0]}, the bundle's camera is "
                                                                  f"{width}x{height}")
        boxes_truth = truth.get(frame.number, np.zeros((0, 4)))
        start = time.perf_counter()
        people: list[Person] = runtime(frame.image)
        records[OURS].add(boxes_truth, np.array([p.box for p in people]), np.array([p.score for p in people]),
                          time.perf_counter() - start)
        lines.append({"frame": frame.number, "people": [person.to_dict() for person in people]})
        for name, detector in others.items():
            start = time.perf_counter()
            boxes, scores = detector(frame.image)
            records[name].add(boxes_truth, boxes, scores, time.perf_counter() - start)
        if index in sheet_numbers:
            sheet.append(draw_people(frame.image, people, truth_boxes=boxes_truth))
    evaluations = {name: evaluate(record.images) for name, record in records.items()}
    metrics = {
        "bundle": str(args.bundle), "scene": runtime.bundle.manifest["scene"], "video": str(args.video),
        "ground_truth": str(args.gt), "frames": {"first": args.frames.first, "last": args.frames.last,
                                                 "step": args.frames.step, "count": source.count},
        "threads": args.threads, "iou_threshold": 0.5,
        "detectors": {name: record.summary(evaluations[name]) for name, record in records.items()},
        "operating_point": operating_point(records[OURS].images, evaluations[OURS]),
    }
    with atomic_directory(args.output) as staging:
        write_json(staging / "metrics.json", metrics)
        plot_precision_recall(evaluations, staging / "precision_recall.png",
                              f"{metrics['scene']}: {source.count} real frames, AP at IoU 0.5")
        write_image(staging / "contact_sheet.png", contact_sheet(sheet))
        (staging / "detections.jsonl").write_text("".join(json.dumps(line) + "\n" for line in lines))
    print(f"vc-eval: {source.count} frames of {args.video.name}, {evaluations[OURS].ground_truth} people -> "
          f"{args.output}")
    for name, summary in metrics["detectors"].items():
        print(f"  {name:32s} AP50 {summary['ap50']:.3f}   {summary['ms_per_frame']['median']:8.1f} ms/frame")
    point = metrics["operating_point"]
    if point:
        print(f"  at score >= {point['score_threshold']}: precision {point['precision']:.3f}, recall "
              f"{point['recall']:.3f}; recall by height: " + ", ".join(
                  f"{label} {value['recall']:.2f} ({value['people']})"
                  for label, value in point["recall_by_height"].items())
              + "; by overlap: " + ", ".join(f"{label} {value['recall']:.2f} ({value['people']})"
                                            for label, value in point["recall_by_overlap"].items()))
    return 0
