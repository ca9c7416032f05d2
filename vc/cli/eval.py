"""``vc-eval``: a bundle on real video frames against ground-truth boxes, beside detectors trained on real photos.

    vc-eval BUNDLE --video V --gt GT.txt -o OUT [--frames first:last:step] [--no-hog] [--hog-upscale F]
            [--external MODEL.onnx [--external-name NAME]]... [--external-size S] [--threads N] [--quiet]

For every selected frame each detector runs and is timed: the bundle (through :mod:`vc.deploy.runtime`, as the
appliance runs it), OpenCV's HOG people detector, and optionally any YOLO-pose style ONNX model. Writes
``OUT/metrics.json`` (AP50, milliseconds per frame, and for the bundle its operating point and recall by person
height, group and region), ``OUT/precision_recall.png``, ``OUT/contact_sheet.png`` (frames with the bundle's people
in colour and the ground truth in white), ``OUT/detections.jsonl``, and the bundle's miss analysis
(:mod:`vc.deploy.misses`): ``OUT/misses.json`` (near misses and misses, the near misses' box errors, false
positives by kind, every error listed), ``OUT/misses.png`` and ``OUT/worst_frames.png`` (the frames of most
errors: truth white when found, orange near missed, red missed; false positives magenta).

GT is in the MOT text format; only frames inside its annotated range can be selected (a frame without a line
there has nobody in it). Bad input exits with status 2.
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
from vc.baselines import Detections, HogPeopleDetector, YoloPoseOnnx
from vc.cli.common import handles_input_errors, positive_int
from vc.deploy.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, PoseAgreement, pose_agreement
from vc.deploy.metrics import Evaluation, ImageResult, evaluate
from vc.deploy.misses import MissAnalysis, analyse_misses, region_lookup
from vc.deploy.runtime import Person, Runtime
from vc.draw import contact_sheet, draw_errors, draw_people
from vc.errors import InputError
from vc.frames import FrameRange, FrameSource
from vc.io import atomic_directory, write_image, write_json
from vc.mot import read_mot_boxes
from vc.plots import plot_miss_analysis, plot_pose_agreement, plot_precision_recall

OURS = "visual compiler"
SHEET_FRAMES = 8


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
    parser.add_argument("--external", type=Path, action="append", default=[],
                        help="a YOLO-pose style ONNX model to compare with (repeatable); the first is the reference "
                             "the bundle's pose is compared with, a second shows the comparison's ceiling")
    parser.add_argument("--external-size", type=positive_int, help="their square input size (if dynamic)")
    parser.add_argument("--external-name", action="append", default=[],
                        help="a label per --external, in order (default: the file name and input size)")
    parser.add_argument("--threads", type=positive_int, default=None, help="threads per detector (default: all)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


@dataclass
class _Record:
    """One detector's results and timings over the frames."""

    images: list[ImageResult] = field(default_factory=list)
    milliseconds: list[float] = field(default_factory=list)

    def add(self, truth: np.ndarray, detections: Detections, seconds: float) -> None:
        self.images.append(ImageResult(truth_boxes=truth, boxes=np.asarray(detections.boxes).reshape(-1, 4),
                                       scores=np.asarray(detections.scores, np.float64).ravel(),
                                       keypoints=detections.keypoints))
        self.milliseconds.append(seconds * 1e3)

    def summary(self, evaluation: Evaluation) -> dict:
        return {"ap50": round(evaluation.ap50, 4), "ground_truth": evaluation.ground_truth,
                "detections": int(len(evaluation.scores)),
                "ms_per_frame": {"median": round(float(np.median(self.milliseconds)), 2),
                                 "mean": round(float(np.mean(self.milliseconds)), 2)}}


def _detectors(args: argparse.Namespace) -> dict:
    detectors = {}
    if not args.no_hog:
        detectors["HOG (OpenCV, real photos)"] = HogPeopleDetector(args.hog_upscale)
    if len(args.external_name) > len(args.external):
        raise InputError(None, "--external-name", f"{len(args.external_name)} names for {len(args.external)} models")
    for index, path in enumerate(args.external):
        model = YoloPoseOnnx(path, args.external_size, args.threads)
        name = args.external_name[index] if index < len(args.external_name) else f"{path.name} @{model.size}"
        if name in detectors or name == OURS:
            raise InputError(path, "--external-name", f"the label {name!r} is taken; give each model its own")
        detectors[name] = model
    return detectors


def _check_selection(source: FrameSource, truth: dict[int, np.ndarray], gt_path: Path) -> None:
    last_annotated = max(truth)
    beyond = source.frames.last is None or source.frames.last > last_annotated
    if beyond and source.count > source.frames.count(last_annotated):
        raise InputError(gt_path, "frames", f"the selection reaches past the last annotated frame "
                                            f"({last_annotated}); select with --frames first:{last_annotated}:step")


def _pose_agreements(records: dict[str, _Record], others: list[str]) -> dict[str, dict[str, PoseAgreement]]:
    """{reference: {detector: agreement}}: the bundle and every other pose model against the first external pose
    model (none without one)."""
    with_pose = [name for name in others if any(image.keypoints is not None for image in records[name].images)]
    if not with_pose:
        return {}
    reference = with_pose[0]
    return {reference: {name: pose_agreement(records[name].images, records[reference].images)
                        for name in [OURS, *with_pose[1:]]}}


def _rates(rates: dict) -> str:
    return ", ".join(f"{label} {value['recall']:.2f} ({value['people']})" for label, value in rates.items())


def _miss_summary(misses: MissAnalysis) -> str:
    outcomes, kinds, near = misses.outcomes(), misses.false_positive_kinds(), misses.near_miss_errors()
    lines = [f"  at score >= {misses.score_threshold:.3f}: precision {misses.precision:.3f}, recall "
             f"{misses.recall:.3f}; not found {outcomes['near miss'] + outcomes['missed']}: {outcomes['near miss']} "
             f"near misses, {outcomes['missed']} with nothing near",
             f"  recall by height: {_rates(misses.recall_by_height())}",
             f"  by overlap: {_rates(misses.recall_by_group())}; by region: {_rates(misses.recall_by_region())}",
             "  false positives: " + ", ".join(f"{count} {kind}" for kind, count in kinds.items())]
    if near["width_ratio"] is not None:
        lines.append(f"  near misses: width x{near['width_ratio']['median']:.2f}, height "
                     f"x{near['height_ratio']['median']:.2f}, |offset| {near['abs_x_offset']['median']:.2f} widths; "
                     f"{near['neighbour_box']} were a neighbour's box")
    return "\n".join(lines)


def _write_miss_analysis(folder: Path, misses: MissAnalysis, video: Path, frames: FrameRange,
                         people_by_frame: dict[int, list[Person]], title: str) -> None:
    """``misses.json``, ``misses.png`` and ``worst_frames.png`` (the frames of most errors, read again)."""
    write_json(folder / "misses.json", misses.to_dict())
    plot_miss_analysis(misses, folder / "misses.png", title)
    worst = set(misses.worst_frames(SHEET_FRAMES))
    if not worst:
        return
    sheet = [draw_errors(frame.image, frame.number, people_by_frame[frame.number],
                         [person for person in misses.people if person.frame == frame.number],
                         [false for false in misses.false_positives if false.frame == frame.number])
             for frame in FrameSource(video, frames) if frame.number in worst]
    write_image(folder / "worst_frames.png", contact_sheet(sheet))


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
    sheet, lines, people_by_frame = [], [], {}
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
        seconds = time.perf_counter() - start
        records[OURS].add(boxes_truth, Detections(np.array([p.box for p in people]).reshape(-1, 4),
                                                  np.array([p.score for p in people]),
                                                  np.array([p.keypoints for p in people]).reshape(-1, 17, 3)),
                          seconds)
        lines.append({"frame": frame.number, "people": [person.to_dict() for person in people]})
        people_by_frame[frame.number] = people
        for name, detector in others.items():
            start = time.perf_counter()
            detections = detector(frame.image)
            records[name].add(boxes_truth, detections, time.perf_counter() - start)
        if index in sheet_numbers:
            sheet.append(draw_people(frame.image, people, truth_boxes=boxes_truth))
    runtime.close()
    evaluations = {name: evaluate(record.images) for name, record in records.items()}
    areas = {entry.name: entry.owned_image_area for entry in runtime.bundle.regions}
    misses = analyse_misses(records[OURS].images, list(people_by_frame), region_lookup(areas))
    agreements = _pose_agreements(records, list(others))
    metrics = {
        "bundle": str(args.bundle), "scene": runtime.bundle.manifest["scene"], "video": str(args.video),
        "ground_truth": str(args.gt), "frames": {"first": args.frames.first, "last": args.frames.last,
                                                 "step": args.frames.step, "count": source.count},
        "threads": args.threads, "iou_threshold": 0.5,
        "detectors": {name: record.summary(evaluations[name]) for name, record in records.items()},
        "operating_point": misses.summary() if misses is not None else {},
        **({"pose_agreement": {"reference": next(iter(agreements)), "reference_confidence": REFERENCE_CONFIDENCE,
                               "within_head_sizes": AGREEMENT_HEAD_SIZES,
                               "agreement": {name: agreement.to_dict()
                                             for name, agreement in agreements[next(iter(agreements))].items()}}}
           if agreements else {}),
    }
    with atomic_directory(args.output) as staging:
        write_json(staging / "metrics.json", metrics)
        plot_precision_recall(evaluations, staging / "precision_recall.png",
                              f"{metrics['scene']}: {source.count} real frames, AP at IoU 0.5")
        write_image(staging / "contact_sheet.png", contact_sheet(sheet))
        (staging / "detections.jsonl").write_text("".join(json.dumps(line) + "\n" for line in lines))
        if agreements:
            reference = next(iter(agreements))
            plot_pose_agreement(agreements[reference], staging / "pose_agreement.png",
                                f"{metrics['scene']}: keypoints within {AGREEMENT_HEAD_SIZES} head sizes of "
                                f"{reference}'s confident ones (conf >= {REFERENCE_CONFIDENCE})")
        if misses is not None:
            _write_miss_analysis(staging, misses, args.video, args.frames, people_by_frame,
                                 f"{metrics['scene']}: {source.count} real frames")
    print(f"vc-eval: {source.count} frames of {args.video.name}, {evaluations[OURS].ground_truth} people -> "
          f"{args.output}")
    for name, summary in metrics["detectors"].items():
        print(f"  {name:32s} AP50 {summary['ap50']:.3f}   {summary['ms_per_frame']['median']:8.1f} ms/frame")
    if misses is not None:
        print(_miss_summary(misses))
    for reference, by_name in agreements.items():
        for name, agreement in by_name.items():
            overall = "n/a" if agreement.overall is None else f"{agreement.overall:.3f}"
            print(f"  pose agreement with {reference}: {name} {overall} ({agreement.people} people)")
    return 0
