"""The evaluate stage: a bundle on real video frames against ground-truth boxes, beside detectors trained on real
photos (OpenCV's HOG, YOLO-pose style ONNX models), with the bundle's miss analysis and its pose agreement with
the first external pose model. What ``vc-eval`` runs and what the benchmarks call.

With a video (or a folder of frames and its frame rate) the bundle runs on every frame from the first selected
to the last, as an appliance would, and its people are tracked (:mod:`vc.deploy.tracking`): their walking
direction decides which way they face where the network cannot tell, and a person lost for a moment is carried
by their track. The bundle is then also scored each frame on its own (:data:`OURS_SINGLE_FRAME`), so that one run
shows what tracking adds. Only the selected frames are scored and timed.

Every detector's AP50 is also given inside the area the ground truth annotates (:mod:`vc.evaluation.annotated_area`),
where a detection of someone the annotation leaves out is not counted against it: beside the plain AP50, which
stays the headline.

Writes into ``output`` (complete or not at all): ``metrics.json`` (AP50, milliseconds per frame, for the bundle
its operating point and recall by person height, group and region, how soon the people coming into view are found
(:mod:`vc.evaluation.arrivals`), and the scored frames per scene fitness state,
:mod:`vc.deploy.fitness`), ``precision_recall.png``,
``contact_sheet.png`` (frames with the bundle's people in colour and the ground truth in white),
``detections.jsonl``, ``pose_agreement.png`` (with an external pose model) and the bundle's miss analysis
(:mod:`vc.evaluation.misses`): ``misses.json``, ``misses.png`` and ``worst_frames.png``.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from vc.deploy.engines import DEFAULT_ENGINE
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import DEFAULT_UNFIT, Person, Runtime
from vc.deploy.tracking import Tracker, TrackingConfig, tracking_rate
from vc.errors import InputError
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, PoseAgreement, pose_agreement
from vc.evaluation.annotated_area import AnnotatedArea
from vc.evaluation.arrivals import arrivals
from vc.evaluation.arrivals import summarise as summarise_arrivals
from vc.evaluation.baselines import Detections, HogPeopleDetector, YoloPoseOnnx
from vc.evaluation.draw import contact_sheet, draw_errors, draw_people
from vc.evaluation.metrics import Evaluation, ImageResult, evaluate
from vc.evaluation.misses import MissAnalysis, analyse_misses, region_lookup
from vc.evaluation.mot import read_mot_boxes, read_mot_ids
from vc.evaluation.plots import plot_miss_analysis, plot_pose_agreement, plot_precision_recall
from vc.evaluation.tracks import FrameTracks, TrackAccuracy, track_accuracy
from vc.io import atomic_directory, write_image, write_json

OURS = "visual compiler"
#: The bundle's people before tracking, scored beside the tracked ones: what tracking adds.
OURS_SINGLE_FRAME = f"{OURS}, each frame on its own"
SHEET_FRAMES = 8
HOG_UPSCALE = 2.0  # HOG's smallest window is 128 px tall: PETS09's people are 50-100 px


@dataclass(frozen=True)
class ExternalModel:
    """A YOLO-pose style ONNX model to compare with; ``name`` labels it (default: the file name and input size)."""

    path: Path
    name: str | None = None


@dataclass(frozen=True)
class EvaluationRequest:
    bundle: Path
    video: Path  # a video file or a folder of frames
    ground_truth: Path  # MOT text format
    output: Path
    frames: FrameRange | None = None  # None: every annotated frame
    hog: bool = True
    hog_upscale: float = HOG_UPSCALE
    externals: tuple[ExternalModel, ...] = ()  # the first with keypoints is the pose reference
    external_size: int | None = None  # their square input size (if dynamic)
    threads: int | None = None  # per detector; None: all cores
    # People tracked over every frame between the first and last selected (an appliance sees every frame), their
    # walking direction deciding which way they face (vc.deploy.tracking); None: each frame on its own.
    tracking: TrackingConfig | None = TrackingConfig()
    fps: float | None = None  # of a folder of frames (a video's is read from it); without it a folder is not tracked
    unfit: str = DEFAULT_UNFIT  # the people of an unfit frame: withheld or flagged (vc.deploy.runtime.UNFIT_SETTINGS)
    engine: str = DEFAULT_ENGINE  # what runs the bundle's networks (vc.deploy.engines)


@dataclass
class EvaluationReport:
    metrics: dict  # metrics.json's content
    evaluations: dict[str, Evaluation]
    misses: MissAnalysis | None
    agreements: dict[str, dict[str, PoseAgreement]]  # {reference: {detector: agreement}}
    frames: int
    video: Path


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

    def summary(self, evaluation: Evaluation, inside_area: Evaluation) -> dict:
        return {"ap50": round(evaluation.ap50, 4), "ap50_in_annotated_area": round(inside_area.ap50, 4),
                "ground_truth": evaluation.ground_truth,
                "detections": int(len(evaluation.scores)),
                "ms_per_frame": {"median": round(float(np.median(self.milliseconds)), 2),
                                 "mean": round(float(np.mean(self.milliseconds)), 2)}}


def _detectors(request: EvaluationRequest) -> dict:
    detectors = {}
    if request.hog:
        detectors["HOG (OpenCV, real photos)"] = HogPeopleDetector(request.hog_upscale)
    for external in request.externals:
        model = YoloPoseOnnx(external.path, request.external_size, request.threads)
        name = external.name or f"{external.path.name} @{model.size}"
        if name in detectors or name in (OURS, OURS_SINGLE_FRAME):
            raise InputError(external.path, "--external-name", f"the label {name!r} is taken; give each model its "
                                                               "own")
        detectors[name] = model
    return detectors


def _check_selection(source: FrameSource, truth: dict[int, np.ndarray], gt_path: Path) -> None:
    last_annotated = max(truth)
    beyond = source.frames.last is None or source.frames.last > last_annotated
    if beyond and source.count > source.frames.count(last_annotated):
        raise InputError(gt_path, "frames", f"the selection reaches past the last annotated frame "
                                            f"({last_annotated}); select with --frames first:{last_annotated}:step")


def _pose_agreements(records: dict[str, _Record], others: list[str]) -> dict[str, dict[str, PoseAgreement]]:
    """{reference: {detector: agreement}}: the bundle (tracked and, when it is, each frame on its own) and every
    other pose model against the first external pose model (none without one)."""
    with_pose = [name for name in others if any(image.keypoints is not None for image in records[name].images)]
    if not with_pose:
        return {}
    reference = with_pose[0]
    ours = [name for name in (OURS, OURS_SINGLE_FRAME) if name in records]
    return {reference: {name: pose_agreement(records[name].images, records[reference].images)
                        for name in [*ours, *with_pose[1:]]}}


def _detections(people: list[Person]) -> Detections:
    return Detections(np.array([p.box for p in people]).reshape(-1, 4), np.array([p.score for p in people]),
                      np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def _track_accuracy(images: list[ImageResult], people_by_frame: dict[int, list[Person]],
                    identities: list[np.ndarray], score_threshold: float) -> TrackAccuracy:
    """The tracks' CLEAR MOT and IDF1 at the operating point (:mod:`vc.evaluation.tracks`)."""
    return track_accuracy([FrameTracks(image.truth_boxes, ids, image.boxes, image.scores,
                                       np.array([person.track for person in people], int))
                           for image, ids, people in zip(images, identities, people_by_frame.values(), strict=True)],
                          score_threshold)


def _write_miss_analysis(folder: Path, misses: MissAnalysis, video: Path, frames: FrameRange,
                         people_by_frame: dict[int, list[Person]], title: str, annotated_area: AnnotatedArea,
                         arrivals_summary: dict) -> None:
    """``misses.json``, ``misses.png`` (with the ``arrivals_summary``) and ``worst_frames.png`` (the frames of most
    errors, read again, with the annotated area outlined)."""
    write_json(folder / "misses.json", misses.to_dict())
    plot_miss_analysis(misses, folder / "misses.png", title, arrivals_summary)
    worst = set(misses.worst_frames(SHEET_FRAMES))
    if not worst:
        return
    sheet = [draw_errors(frame.image, frame.number, people_by_frame[frame.number],
                         [person for person in misses.people if person.frame == frame.number],
                         [false for false in misses.false_positives if false.frame == frame.number],
                         annotated_area.polygon)
             for frame in FrameSource(video, frames) if frame.number in worst]
    write_image(folder / "worst_frames.png", contact_sheet(sheet))


def evaluate_bundle(request: EvaluationRequest, show_progress: bool = True) -> EvaluationReport:
    """Run every detector on every selected frame (each timed), score them, analyse the bundle's misses and write
    the outputs (see the module's docstring)."""
    truth = read_mot_boxes(request.ground_truth)
    frames = request.frames or FrameRange(1, max(truth))
    source = FrameSource(request.video, frames)
    _check_selection(source, truth, request.ground_truth)
    rate = tracking_rate(source, request.fps) if request.tracking is not None else None
    tracker = Tracker(request.tracking) if rate else None
    with Runtime(request.bundle, threads=request.threads, unfit=request.unfit, engine=request.engine,
                 weak_people_above=request.tracking.weak_people_above if tracker else None) as runtime:
        if request.threads:
            cv2.setNumThreads(request.threads)
        others = _detectors(request)
        records = {OURS: _Record(), **({OURS_SINGLE_FRAME: _Record()} if tracker else {}),
                   **{name: _Record() for name in others}}
        sheet_numbers = set(np.linspace(0, source.count - 1, min(SHEET_FRAMES, source.count)).round().astype(int))
        sheet, lines, people_by_frame, fitnesses = [], [], {}, []
        width, height = runtime.bundle.frame_size
        # A tracker sees every frame from the first selected to the last; only the selected ones are scored.
        seen = (FrameSource(request.video, FrameRange(frames.first, frames.last or max(truth), 1)) if tracker
                else source)
        progress = tqdm(total=len(source), desc="vc-eval", unit="frame", disable=not show_progress)
        for frame in seen:
            if frame.image.shape != (height, width, 3):
                raise InputError(request.video, f"frame {frame.number}",
                                 f"is {frame.image.shape[1]}x{frame.image.shape[0]}, the bundle's camera is "
                                 f"{width}x{height}")
            scored = frame.number in frames
            start = time.perf_counter()
            result = runtime.run(frame.image)
            people: list[Person] = result.people
            single_frame_seconds = time.perf_counter() - start
            on_its_own = [person for person in people if not person.weak]  # what the bundle reports without a tracker
            tracked = result.reported(tracker.update(people, frame.number / rate, frame.image)) if tracker else people
            seconds = time.perf_counter() - start
            if not scored:
                continue
            fitnesses.append(result.fitness)
            boxes_truth = truth.get(frame.number, np.zeros((0, 4)))
            records[OURS].add(boxes_truth, _detections(tracked), seconds)
            if tracker:
                records[OURS_SINGLE_FRAME].add(boxes_truth, _detections(on_its_own), single_frame_seconds)
            lines.append({"frame": frame.number, "people": [person.to_dict() for person in tracked]})
            people_by_frame[frame.number] = tracked
            for name, detector in others.items():
                start = time.perf_counter()
                detections = detector(frame.image)
                records[name].add(boxes_truth, detections, time.perf_counter() - start)
            if len(people_by_frame) - 1 in sheet_numbers:
                sheet.append(draw_people(frame.image, tracked, truth_boxes=boxes_truth))
            progress.update()
        progress.close()
        bundle = runtime.bundle
        fitness = runtime.fitness_summary(fitnesses)
    evaluations = {name: evaluate(record.images) for name, record in records.items()}
    annotated_area = AnnotatedArea.of(truth)
    areas = {entry.name: entry.owned_image_area for entry in bundle.regions}
    ids = read_mot_ids(request.ground_truth)
    identities = [ids.get(number, np.zeros(0, int)) for number in people_by_frame]
    misses = analyse_misses(records[OURS].images, list(people_by_frame), region_lookup(areas), annotated_area,
                            bundle.frame_size, identities)
    agreements = _pose_agreements(records, list(others))
    tracking = ({"fps": rate, "config": asdict(request.tracking)} if tracker else
                {"off": "--no-tracking" if request.tracking is None else
                 "the frames' times are unknown (a folder of frames: give --fps)"})
    if tracker and misses is not None:
        tracking["accuracy"] = _track_accuracy(records[OURS].images, people_by_frame, identities,
                                               misses.score_threshold).to_dict()
    followed = arrivals(misses.people, list(people_by_frame)) if misses is not None else []
    metrics = {
        "bundle": str(request.bundle), "scene": bundle.manifest["scene"], "video": str(request.video),
        "ground_truth": str(request.ground_truth), "frames": {"first": frames.first, "last": frames.last,
                                                             "step": frames.step, "count": source.count},
        "threads": request.threads, "engine": request.engine, "iou_threshold": 0.5,
        "tracking": tracking,
        "annotated_area": annotated_area.to_dict(),
        "detectors": {name: record.summary(evaluations[name], annotated_area.evaluate_inside(record.images))
                      for name, record in records.items()},
        "operating_point": misses.summary() if misses is not None else {},
        "arrivals": {"summary": summarise_arrivals(followed, rate),
                     "people": [arrival.to_dict() for arrival in followed]},
        "fitness": fitness,
        **({"pose_agreement": {"reference": next(iter(agreements)), "reference_confidence": REFERENCE_CONFIDENCE,
                               "within_head_sizes": AGREEMENT_HEAD_SIZES,
                               "agreement": {name: agreement.to_dict()
                                             for name, agreement in agreements[next(iter(agreements))].items()}}}
           if agreements else {}),
    }
    with atomic_directory(request.output) as staging:
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
            _write_miss_analysis(staging, misses, request.video, frames, people_by_frame,
                                 f"{metrics['scene']}: {source.count} real frames", annotated_area,
                                 metrics["arrivals"]["summary"])
    return EvaluationReport(metrics, evaluations, misses, agreements, source.count, request.video)
