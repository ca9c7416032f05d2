"""How a bundle holds up when the camera's picture changes: COCO-C's common corruptions and the changes a camera meets
every day (exposure, white balance, night IR, blur, a nudge, a roll, a lost signal), beside a YOLO-pose model on the
same frames in the same run.

    python -m benchmarks.robustness BUNDLE --video V --gt GT.txt [--frames 1:400:5] [--background IMAGE]
        [--external MODEL.onnx [--external-size S]] [--corruptions NAME ...] [--severities 1 3 5]
        [--conditions KEY ...] [--nudge 12] [--roll 0.5] [--threads 2] [--out DIR] [--quiet]

Every selected frame is changed by every condition and run, each frame on its own (no tracking), by the bundle
(:class:`vc.deploy.runtime.Runtime`, as an appliance runs it) and by the ``--external`` model
(:class:`vc.evaluation.baselines.YoloPoseOnnx`), and scored against the ground truth, which moves with the image
where the condition moves it (a nudged or rolled camera). The conditions:

- **clean**: the frames as recorded; the reference of rPC and of the bundle's operating point.
- **COCO-C** (Michaelis et al., "Benchmarking Robustness in Object Detection", 2019): the 15 common corruptions of
  the ``imagecorruptions`` module (noise, blur, weather, digital) at ``--severities`` (default 1-5). ``--corruptions``
  picks some; ``--corruptions`` with no name skips them. The module's own PyPI package (1.1.2) does not run with
  numpy 2: it comes from ``imagecorruptions-imaug``, the same code ported, installed without its dependencies
  (``pyproject.toml``'s ``robustness`` extra says why).
- **camera life** (:func:`camera_life_conditions`; ``--conditions`` picks by key): exposure -2, -3 and +1 stops,
  white balance warm and cool, IR monochrome, Gaussian blur, the camera nudged by ``--nudge`` px and rolled by
  ``--roll`` degrees, and three frames that replace the scene, scored on the background only: black, uniform grey,
  noise.

Random conditions are seeded per condition and frame (:func:`condition_seed`): a rerun changes the frames to the
same bytes. Each condition starts the bundle's runtime afresh (:meth:`vc.deploy.runtime.Runtime.reset`): what it
carries from frame to frame, a moved view's registration above all, is a camera's, not one condition's to the next.

Measured per condition: AP50 of each detector (:func:`vc.evaluation.metrics.evaluate`) and the scene fitness states the
bundle's runtime gave the frames (:mod:`vc.deploy.fitness`: what it withheld, flagged or ran, and which it brought back
from light or a veil beyond the range first); per family, mPC (the mean
AP50 over its conditions: for COCO-C over corruptions and severities) and rPC (mPC / clean AP50); and with
``--background`` (the scene's empty background, e.g. ``background.png`` of the compile), the people each detector
reports on it under every condition (truth: nobody), counted for the bundle at its operating point — the score threshold
of best F1 on this run's clean frames, as ``vc-eval`` defines it (:func:`vc.evaluation.misses.operating_point`) — and as
it reports them (every person above the bundle's own centre threshold: what ``vc-run`` writes), and for the external
model at score >= :data:`EXTERNAL_SCORE` (Ultralytics' default confidence). AP50, mPC and rPC are also reported on
each half of the frames, the choosing and the confirming (:mod:`benchmarks.protocol`). Writes ``robustness.json``,
``robustness.md`` and ``robustness.png`` to ``--out`` (``benchmarks/results/robustness/``), naming the machine, the
bundle, the frames and the command. """

from __future__ import annotations

import argparse
import functools
import inspect
import shlex
import time
import zlib
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import cv2
import matplotlib
import numpy as np
from tqdm import tqdm

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from benchmarks import display_path, results_folder  # noqa: E402
from benchmarks.protocol import positions_by_half  # noqa: E402
from vc.calibration.materials import luminance  # noqa: E402
from vc.calibration.response import Response  # noqa: E402
from vc.cores import cpu_facts, usable_cores  # noqa: E402
from vc.deploy.frames import Frame, FrameRange, FrameSource, read_frame_image  # noqa: E402
from vc.deploy.registration import Registration  # noqa: E402
from vc.deploy.runtime import DEFAULT_UNFIT, UNFIT_SETTINGS, Runtime  # noqa: E402
from vc.errors import InputError  # noqa: E402
from vc.evaluation.baselines import Detections, YoloPoseOnnx  # noqa: E402
from vc.evaluation.metrics import ImageResult, evaluate  # noqa: E402
from vc.evaluation.misses import operating_point  # noqa: E402
from vc.evaluation.mot import read_mot_boxes  # noqa: E402
from vc.evaluation.real_video import OURS  # noqa: E402
from vc.io import write_json  # noqa: E402

CLEAN, CAMERA_LIFE, COCO_C = "clean", "camera life", "COCO-C"
#: The external model's people counted on the empty background: Ultralytics' default confidence threshold.
EXTERNAL_SCORE = 0.25
#: How far the camera is nudged by default, in pixels of image content (the issue's measurement).
NUDGE_PX = 12
#: How far the camera is rolled by default, in degrees about the frame's centre: a bracket that settled (issue 62's
#: "a fraction of a degree").
ROLL_DEG = 0.5
#: The level of the uniform grey frame (a covered lens, a camera's grey "no signal" picture).
GREY_LEVEL = 128
#: A truth box of which less than this share of the width is still in the frame after the camera moved is not asked
#: for.
VISIBLE_SHARE = 0.5
SEVERITIES = (1, 2, 3, 4, 5)
#: The camera's transfer curve the light conditions go through (IEC 61966-2-1; the composites are encoded with it).
SRGB = Response("srgb")
#: The false-people counts, by what they count.
AT_OPERATING_POINT = f"{OURS} at its operating point"
AS_REPORTED = f"{OURS}, every person reported"


# ---------------------------------------------------------------- camera-life conditions: pure functions of a frame

def exposure(frame: np.ndarray, stops: float) -> np.ndarray:
    """``frame`` (H, W, 3) uint8 sRGB with ``stops`` more light (negative: less): decoded through the sRGB curve
    (IEC 61966-2-1) to linear light, scaled by 2**stops, clipped at the sensor's white and encoded back. -2 stops is
    a quarter of the light, not half the pixel value (which is about -2.2 stops on the curve's straight part)."""
    return SRGB.encode(SRGB.decode(frame) * np.float32(2.0 ** stops))


def white_balance(frame: np.ndarray, red: float, blue: float) -> np.ndarray:
    """``frame`` with its red and blue channels scaled by ``red`` and ``blue`` in linear light (decoded through the
    sRGB curve, clipped, encoded back): a white balance set for other light. Warm: red > 1 > blue."""
    gains = np.array([red, 1.0, blue], np.float32)
    return SRGB.encode(SRGB.decode(frame) * gains)


def ir_monochrome(frame: np.ndarray) -> np.ndarray:
    """``frame`` as a camera's night mode shows it: the relative luminance of its linear light (sRGB primaries,
    :func:`vc.calibration.materials.luminance`) encoded back and replicated to the three channels. (Under IR
    illumination the scene's brightness differs too; this keeps the visible luminance.)"""
    grey = SRGB.encode(luminance(SRGB.decode(frame)).astype(np.float32))
    return np.repeat(grey[..., None], 3, axis=-1)


def gaussian_blur(frame: np.ndarray, sigma: float) -> np.ndarray:
    """``frame`` blurred by a Gaussian of ``sigma`` pixels (OpenCV, kernel sized from sigma, borders reflected): a
    dirty lens or focus drift."""
    return cv2.GaussianBlur(frame, (0, 0), sigmaX=sigma, sigmaY=sigma)


def nudge(frame: np.ndarray, dx: int, dy: int = 0) -> np.ndarray:
    """``frame``'s content moved by ``dx`` px right and ``dy`` px down (negative: left, up), the uncovered edge filled
    by replicating the last row or column: a camera whose bracket moved (:func:`moved_boxes` moves the truth)."""
    height, width = frame.shape[:2]
    rows = np.clip(np.arange(height) - dy, 0, height - 1)
    columns = np.clip(np.arange(width) - dx, 0, width - 1)
    return frame[rows[:, None], columns[None, :]]


def roll(frame: np.ndarray, degrees: float) -> np.ndarray:
    """``frame``'s content turned by ``degrees`` counter-clockwise about the frame's centre (a camera's principal
    point lies near it), bilinear, the uncovered corners filled by replicating the edge: a camera rolled on its bracket
    (:func:`moved_boxes` moves the truth)."""
    height, width = frame.shape[:2]
    return cv2.warpAffine(frame, image_motion((width, height), roll_deg=degrees), (width, height),
                          flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)


def image_motion(frame_size: tuple[int, int], shift: tuple[int, int] = (0, 0), roll_deg: float = 0.0) -> np.ndarray:
    """The (2, 3) affine map of a frame's content (``frame_size``: width, height) turned by ``roll_deg``
    counter-clockwise about the frame's centre, then moved by ``shift`` (x, y) px: the runtime's own
    (:meth:`vc.deploy.registration.Registration.matrix`), which undoes it."""
    return Registration(int(shift[0]), int(shift[1]), float(roll_deg)).matrix(frame_size)


def moved_boxes(boxes: np.ndarray, motion: np.ndarray, frame_size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Truth boxes (N, 4) moved with the frame's content by ``motion`` (:func:`image_motion`) and clipped to the frame
    (``frame_size``: width, height), and which of them to ignore: those with less than :data:`VISIBLE_SHARE` of their
    width still in the frame (neither a miss nor a match: :mod:`vc.evaluation.metrics`). A box's centre follows the
    content and its size is kept: a person turned by a degree keeps the box an annotator draws to within a pixel or
    two, where the box of its turned corners would widen by a tenth of a pedestrian's width."""
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    width, height = frame_size
    # a box's coordinates are at the pixels' edges, the motion's at their centres (OpenCV's)
    centres = np.column_stack([(boxes[:, 0] + boxes[:, 2]) / 2 - 0.5, (boxes[:, 1] + boxes[:, 3]) / 2 - 0.5,
                               np.ones(len(boxes))])
    offsets = centres @ np.asarray(motion, np.float64).T - centres[:, :2]
    moved = boxes + np.column_stack([offsets, offsets])
    clipped = np.column_stack([np.clip(moved[:, [0, 2]], 0, width), np.clip(moved[:, [1, 3]], 0, height)])[
        :, [0, 2, 1, 3]]
    widths = np.maximum(boxes[:, 2] - boxes[:, 0], 1e-9)
    return clipped, (clipped[:, 2] - clipped[:, 0]) / widths < VISIBLE_SHARE


def black_frame(frame: np.ndarray) -> np.ndarray:
    """A frame of ``frame``'s size with no light at all: a lost signal or a covered lens."""
    return np.zeros_like(frame)


def grey_frame(frame: np.ndarray, level: int = GREY_LEVEL) -> np.ndarray:
    """A uniform frame of value ``level``: a covered lens under light, a camera's grey "no signal" picture."""
    return np.full_like(frame, level)


def noise_frame(frame: np.ndarray, seed: int) -> np.ndarray:
    """A frame of uniform random values (seeded): a failed sensor or a broken link."""
    return np.random.default_rng(seed).integers(0, 256, frame.shape, np.uint8)


# ------------------------------------------------------------------------------------------------- the conditions

@dataclass(frozen=True)
class Condition:
    """One way to change a frame. ``transform(frame, seed)`` -> the changed frame; ``shift`` and ``roll_deg``: how
    far the image content moved (x, y px) and turned about the frame's centre (:func:`image_motion`), which the truth
    follows; ``background_only``: a frame that replaces the scene, scored on the background alone."""

    key: str  # what --conditions and --corruptions name, and the report's key
    label: str
    family: str  # CLEAN, CAMERA_LIFE or COCO_C
    transform: Callable[[np.ndarray, int], np.ndarray]
    parameters: dict = field(default_factory=dict)
    shift: tuple[int, int] = (0, 0)
    roll_deg: float = 0.0
    background_only: bool = False


def _seedless(function: Callable[..., np.ndarray], **parameters) -> Callable[[np.ndarray, int], np.ndarray]:
    return lambda frame, seed: function(frame, **parameters)


def camera_life_conditions(nudge_px: int = NUDGE_PX, roll_deg: float = ROLL_DEG) -> dict[str, Condition]:
    """The camera-life conditions of issue 62's table, by key."""
    warm, cool = {"red": 1.25, "blue": 0.8}, {"red": 0.8, "blue": 1.25}
    conditions = [
        Condition("exposure-2", "exposure -2 stops", CAMERA_LIFE, _seedless(exposure, stops=-2.0), {"stops": -2}),
        Condition("exposure-3", "exposure -3 stops", CAMERA_LIFE, _seedless(exposure, stops=-3.0), {"stops": -3}),
        Condition("exposure+1", "exposure +1 stop", CAMERA_LIFE, _seedless(exposure, stops=1.0), {"stops": 1}),
        Condition("warm", "white balance warm (R x1.25, B x0.8)", CAMERA_LIFE, _seedless(white_balance, **warm),
                  warm),
        Condition("cool", "white balance cool (R x0.8, B x1.25)", CAMERA_LIFE, _seedless(white_balance, **cool),
                  cool),
        Condition("ir", "IR monochrome", CAMERA_LIFE, _seedless(ir_monochrome)),
        Condition("blur", "Gaussian blur sigma 2 px", CAMERA_LIFE, _seedless(gaussian_blur, sigma=2.0),
                  {"sigma_px": 2.0}),
        Condition("nudge", f"camera nudged {nudge_px} px", CAMERA_LIFE, _seedless(nudge, dx=nudge_px, dy=0),
                  {"dx_px": nudge_px, "dy_px": 0}, shift=(nudge_px, 0)),
        Condition("roll", f"camera rolled {roll_deg:g}°", CAMERA_LIFE, _seedless(roll, degrees=roll_deg),
                  {"roll_deg": roll_deg}, roll_deg=roll_deg),
        Condition("black", "black frame", CAMERA_LIFE, _seedless(black_frame), background_only=True),
        Condition("grey", f"uniform grey frame ({GREY_LEVEL})", CAMERA_LIFE, _seedless(grey_frame),
                  {"level": GREY_LEVEL}, background_only=True),
        Condition("noise", "noise frame", CAMERA_LIFE, noise_frame, background_only=True),
    ]
    return {condition.key: condition for condition in conditions}


def imagecorruptions_module():
    """The ``imagecorruptions`` module, or an :class:`InputError` saying how to install it."""
    try:
        import imagecorruptions
    except ImportError as error:
        raise InputError(None, "--corruptions", f"COCO-C needs the imagecorruptions module ({error}): pip install "
                                                "'visual-compiler[robustness]' and then pip install --no-deps "
                                                "imagecorruptions-imaug==1.1.5 (pyproject.toml says why); or give "
                                                "--corruptions with no name to skip them") from None
    return imagecorruptions


def imagecorruptions_version() -> str | None:
    """Which distribution provides ``imagecorruptions``, and its version (None: neither is installed)."""
    for distribution in ("imagecorruptions-imaug", "imagecorruptions"):
        try:
            return f"{distribution} {metadata.version(distribution)}"
        except metadata.PackageNotFoundError:
            continue
    return None


def corrupt(frame: np.ndarray, corruption: str, severity: int, seed: int) -> np.ndarray:
    """``frame`` under COCO-C's ``corruption`` at ``severity``, drawn from ``seed``: the package draws from numpy's
    global generator (seeded here and put back after) and, for the corruptions that take one, from ``seed``."""
    module = imagecorruptions_module()
    function = module.corruption_dict[corruption]
    extra = {"seed": seed} if "seed" in inspect.signature(function).parameters else {}
    state = np.random.get_state()  # noqa: NPY002 - the package draws from the legacy global generator
    try:
        np.random.seed(seed)  # noqa: NPY002
        return module.corrupt(frame, severity=severity, corruption_name=corruption, **extra)
    finally:
        np.random.set_state(state)  # noqa: NPY002


def coco_c_conditions(corruptions: Sequence[str], severities: Sequence[int]) -> list[Condition]:
    """COCO-C's ``corruptions`` at each of ``severities`` (corruption by corruption)."""
    return [Condition(f"{name}/{severity}", f"{name.replace('_', ' ')} {severity}", COCO_C,
                      functools.partial(_corrupt, corruption=name, severity=severity),
                      {"corruption": name, "severity": severity})
            for name in corruptions for severity in severities]


def _corrupt(frame: np.ndarray, seed: int, corruption: str, severity: int) -> np.ndarray:
    return corrupt(frame, corruption, severity, seed)


def clean_condition() -> Condition:
    return Condition(CLEAN, "as recorded", CLEAN, lambda frame, seed: frame)


def condition_seed(condition: str, frame: str) -> int:
    """The seed of ``condition`` on one frame (its number, or ``background``): the same in every run."""
    return zlib.crc32(f"{condition}|{frame}".encode())


# ------------------------------------------------------------------------------------------------ the measurement

def performance_under_corruption(ap50: Sequence[float], clean: float) -> tuple[float, float | None]:
    """(mPC, rPC) of a family of conditions: the mean of their AP50 (for COCO-C over corruptions and severities,
    each corruption at the same severities, so the mean of the corruptions' means) and its ratio to the clean AP50
    (None when the clean AP50 is 0)."""
    mpc = float(np.mean(ap50))
    return mpc, (mpc / clean if clean > 0 else None)


def _images(truth: np.ndarray, ignore: np.ndarray, detections: Detections) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.asarray(detections.boxes, np.float64).reshape(-1, 4),
                       scores=np.asarray(detections.scores, np.float64).ravel(), truth_ignore=ignore)


class BundleDetector:
    """The bundle as an appliance runs it: a frame's people, and the frame's scene fitness state kept for the
    report (what the runtime made of the condition)."""

    def __init__(self, runtime: Runtime) -> None:
        self.runtime = runtime

    def __call__(self, image: np.ndarray) -> Detections:
        people = self.runtime(image)
        return Detections(np.array([person.box for person in people]).reshape(-1, 4),
                          np.array([person.score for person in people], np.float64))

    @property
    def state(self) -> str:
        """The last frame's state, and what the runtime did to its tone before the networks (vc.deploy.exposure,
        vc.deploy.veil)."""
        fitness = self.runtime.last_fitness
        if fitness.exposure_corrected_stops is not None:
            return f"{fitness.state} brought back"
        return f"{fitness.state} veil taken off" if fitness.veil_taken_off is not None else fitness.state


@dataclass
class Measurement:
    """One condition's detections: per detector, the frames' results and the background's scores."""

    condition: Condition
    images: dict[str, list[ImageResult]] = field(default_factory=dict)
    background_scores: dict[str, np.ndarray] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    states: Counter = field(default_factory=Counter)  # the bundle's scene fitness states over the frames


def measure(condition: Condition, frames: Sequence[Frame], truth: dict[int, np.ndarray], background: np.ndarray | None,
            detectors: dict[str, Callable[[np.ndarray], Detections]], progress: tqdm | None = None) -> Measurement:
    """Every frame (and the background) under ``condition``, run by every detector."""
    result = Measurement(condition, {name: [] for name in detectors}, {},
                         {"changing frames": 0.0, **{name: 0.0 for name in detectors}})

    def run(image: np.ndarray, label: str) -> dict[str, Detections]:
        started = time.perf_counter()
        changed = condition.transform(image, condition_seed(condition.key, label))
        result.seconds["changing frames"] += time.perf_counter() - started
        found = {}
        for name, detector in detectors.items():
            started = time.perf_counter()
            found[name] = detector(changed)
            result.seconds[name] += time.perf_counter() - started
            if isinstance(detector, BundleDetector) and label != "background":
                result.states[detector.state] += 1
        return found

    if not condition.background_only:
        for frame in frames:
            height, width = frame.image.shape[:2]
            motion = image_motion((width, height), condition.shift, condition.roll_deg)
            boxes, ignore = moved_boxes(truth.get(frame.number, np.zeros((0, 4))), motion, (width, height))
            for name, detections in run(frame.image, str(frame.number)).items():
                result.images[name].append(_images(boxes, ignore, detections))
            if progress is not None:
                progress.update()
    if background is not None:
        for name, detections in run(background, "background").items():
            result.background_scores[name] = np.asarray(detections.scores, np.float64).ravel()
        if progress is not None:
            progress.update()
    return result


def summarise(measurements: Sequence[Measurement], external: str | None,
              halves: dict[str, list[int]] | None = None) -> dict:
    """The report's numbers: per condition AP50 and false people, per family mPC, rPC and false people per frame,
    the operating points they were counted at; with ``halves`` (each half's positions among the frames:
    :func:`benchmarks.protocol.positions_by_half`) AP50, mPC and rPC on each half too."""
    clean = next(m for m in measurements if m.condition.family == CLEAN)
    point = operating_point(clean.images[OURS]) if clean.images.get(OURS) else None
    threshold = None if point is None else point.threshold
    thresholds = {AT_OPERATING_POINT: threshold, AS_REPORTED: None,
                  **({f"{external} at score >= {EXTERNAL_SCORE}": EXTERNAL_SCORE} if external else {})}
    detectors = [OURS] + ([external] if external else [])
    rows = []
    for m in measurements:
        row = {"key": m.condition.key, "label": m.condition.label, "family": m.condition.family,
               "parameters": m.condition.parameters}
        if not m.condition.background_only and m.images.get(OURS):
            row["ap50"] = {name: round(evaluate(m.images[name]).ap50, 4) for name in detectors}
            if halves:
                row["ap50_by_half"] = {half: {name: round(evaluate([m.images[name][k] for k in positions]).ap50, 4)
                                              for name in detectors} for half, positions in halves.items()}
        if m.background_scores:
            row["false_people"] = {
                AT_OPERATING_POINT: int(np.sum(m.background_scores[OURS] >= (threshold or 0.0))),
                AS_REPORTED: int(len(m.background_scores[OURS])),
                **({f"{external} at score >= {EXTERNAL_SCORE}":
                    int(np.sum(m.background_scores[external] >= EXTERNAL_SCORE))} if external else {})}
        if m.states:
            row["fitness_states"] = dict(sorted(m.states.items(), key=lambda item: -item[1]))
        row["seconds"] = {name: round(value, 2) for name, value in m.seconds.items()}
        rows.append(row)
    clean_row = next(row for m, row in zip(measurements, rows, strict=True) if m is clean)
    families = {}
    for family in (CAMERA_LIFE, COCO_C):
        members = [row for row in rows if row["family"] == family]
        if not members:
            continue
        summary: dict = {"conditions": len(members)}
        scored = [row for row in members if "ap50" in row]
        if scored and "ap50" in clean_row:
            summary["scored_conditions"] = len(scored)
            pairs = {name: performance_under_corruption([row["ap50"][name] for row in scored], clean_row["ap50"][name])
                     for name in detectors}
            summary["mPC"] = {name: round(mpc, 4) for name, (mpc, _) in pairs.items()}
            summary["rPC"] = {name: None if rpc is None else round(rpc, 4) for name, (_, rpc) in pairs.items()}
            summary["min_ap50"] = {name: min(row["ap50"][name] for row in scored) for name in detectors}
            if halves:
                summary["by_half"] = {half: _per_half_pc(scored, clean_row, half, detectors) for half in halves}
        on_background = [row for row in members if "false_people" in row]
        if on_background:
            summary["false_people_per_frame"] = {
                key: round(float(np.mean([row["false_people"][key] for row in on_background])), 3)
                for key in on_background[0]["false_people"]}
        families[family] = summary
    return {"operating_points": thresholds, "conditions": rows, "families": families}


def _per_half_pc(scored: list[dict], clean_row: dict, half: str, detectors: list[str]) -> dict:
    pairs = {name: performance_under_corruption([row["ap50_by_half"][half][name] for row in scored],
                                                clean_row["ap50_by_half"][half][name]) for name in detectors}
    return {"mPC": {name: round(mpc, 4) for name, (mpc, _) in pairs.items()},
            "rPC": {name: None if rpc is None else round(rpc, 4) for name, (_, rpc) in pairs.items()}}


# ---------------------------------------------------------------------------------------------------- the report

def _fmt(value: float | None, digits: int = 3) -> str:
    return "—" if value is None else f"{value:.{digits}f}"


def markdown(report: dict) -> str:
    detectors = report["detectors"]
    counts = list(report["operating_points"])
    frames, bundle = report["frames"], report["bundle"]
    models = ", ".join(f"{region} {digest}" for region, digest in bundle["models_sha256"].items())
    lines = [f"# Robustness: {report['scene']}", "",
             f"Measured on {report['machine']} ({report['threads']} threads), {report['seconds']:.0f} s. "
             f"Bundle `{bundle['path']}` (scene {bundle['scene']} {bundle['scene_hash']}, "
             f"{'/'.join(bundle['precision'])}, models {models}, "
             f"visual-compiler {bundle['visual_compiler']}); {frames['count']} frames of `{report['video']}` "
             f"({frames['first']}:{frames['last'] or ''}:{frames['step']}, {report['people']} people in "
             f"`{report['ground_truth']}`), each frame on its own; empty background "
             + (f"`{report['background']}`" if report["background"] else "not given") + "; "
             + (f"external model `{report['external']}`" if report["external"] else "no external model") + "; "
             f"corruptions from {report['imagecorruptions'] or '—'}.", "",
             f"Command: `{report['command']}`", "",
             "False people on the empty background (truth: nobody) are counted for the bundle at its operating point "
             f"(score >= {_fmt(report['operating_points'][AT_OPERATING_POINT])}, best F1 on the clean frames, as "
             "vc-eval defines it) and as it reports them (every person above its own centre threshold "
             f"{report['centre_thresholds']}, what vc-run writes)"
             + (f", and for {report['external']} at score >= {EXTERNAL_SCORE}." if report["external"] else "."), "",
             "## Per family", "",
             "| family | conditions | " + " | ".join(f"mPC {name} | rPC {name}" for name in detectors)
             + " | " + " | ".join(f"false people per frame: {key}" for key in counts) + " |",
             "|---|---|" + "---|---|" * len(detectors) + "---|" * len(counts)]
    clean = next(row for row in report["conditions"] if row["family"] == CLEAN)
    if "ap50" in clean:
        lines.append("| clean (AP50) | 1 | " + " | ".join(f"{clean['ap50'][name]:.3f} | 1" for name in detectors)
                     + " | " + " | ".join(str(clean.get("false_people", {}).get(key, "—")) for key in counts) + " |")
    for family, summary in report["families"].items():
        mpc, rpc, people = summary.get("mPC", {}), summary.get("rPC", {}), summary.get("false_people_per_frame", {})
        lines.append(f"| {family} | {summary['conditions']} | "
                     + " | ".join(f"{_fmt(mpc.get(name))} | {_fmt(rpc.get(name))}" for name in detectors)
                     + " | " + " | ".join(_fmt(people.get(key), 2) for key in counts) + " |")
    lines += _halves_lines(report)
    lines += ["", "## Per condition", "",
              "| condition | family | " + " | ".join(f"AP50 {name}" for name in detectors) + " | "
              + " | ".join(f"false people: {key}" for key in counts) + " | scene fitness of the frames |",
              "|---|---|" + "---|" * (len(detectors) + len(counts) + 1)]
    for row in report["conditions"]:
        ap, people = row.get("ap50", {}), row.get("false_people", {})
        states = ", ".join(f"{state} {count}" for state, count in row.get("fitness_states", {}).items()) or "—"
        lines.append(f"| {row['label']} | {row['family']} | "
                     + " | ".join(_fmt(ap.get(name)) for name in detectors) + " | "
                     + " | ".join(str(people.get(key, "—")) for key in counts) + f" | {states} |")
    lines += ["", "![AP50 and false people per condition](robustness.png)", ""]
    return "\n".join(lines)


def _halves_lines(report: dict) -> list[str]:
    """The choosing and confirming halves' clean AP50, mPC and rPC (docs/evaluation.md#choosing-and-confirming)."""
    halves = report.get("halves")
    clean = next(row for row in report["conditions"] if row["family"] == CLEAN)
    if not halves or "ap50_by_half" not in clean:
        return []
    detectors, families = report["detectors"], [f for f, s in report["families"].items() if "by_half" in s]
    lines = ["", "## Choosing and confirming halves", "",
             "A setting is chosen on the first half of the frames and kept only if it holds on the second "
             "(docs/evaluation.md).", "",
             "| half | frames | " + " | ".join(f"clean AP50 {name}" for name in detectors) + " | "
             + " | ".join(f"{family} {kind} {name}" for family in families for name in detectors
                          for kind in ("mPC", "rPC")) + " |",
             "|---|---|" + "---|" * (len(detectors) * (1 + 2 * len(families)))]
    for half, frames in halves.items():
        by_half = [report["families"][family]["by_half"][half] for family in families]
        lines.append(f"| {half} | {frames['first']}–{frames['last']} ({frames['count']}) | "
                     + " | ".join(_fmt(clean["ap50_by_half"][half][name]) for name in detectors) + " | "
                     + " | ".join(f"{_fmt(summary['mPC'][name])} | {_fmt(summary['rPC'][name])}"
                                  for summary in by_half for name in detectors) + " |")
    return lines


def _figure_columns(report: dict) -> list[tuple[str, list[dict]]]:
    """The figure's columns: each condition, COCO-C's severities of one corruption together."""
    columns: list[tuple[str, list[dict]]] = []
    for row in report["conditions"]:
        if row["family"] == COCO_C:
            name = row["parameters"]["corruption"].replace("_", " ")
            if columns and columns[-1][0] == name:
                columns[-1][1].append(row)
                continue
            columns.append((name, [row]))
        else:
            columns.append((row["label"], [row]))
    return columns


def plot(report: dict, path: Path) -> None:
    """AP50 per condition for each detector (COCO-C: the mean over the severities, each severity a dot; the clean
    AP50 dashed) and the people reported per condition on the empty background, families apart."""
    columns = _figure_columns(report)
    detectors, counts = report["detectors"], list(report["operating_points"])
    x = np.arange(len(columns))
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(max(8.0, 0.45 * len(columns) + 2.5), 9.0), sharex=True)
    width = 0.8 / max(len(detectors), 1)
    for index, name in enumerate(detectors):
        means = [np.mean([row["ap50"][name] for row in rows]) if "ap50" in rows[0] else np.nan for _, rows in columns]
        offset = (index - (len(detectors) - 1) / 2) * width
        top.bar(x + offset, means, width, label=name, color=f"C{index}")
        top.axhline(means[0], color=f"C{index}", linestyle="--", linewidth=0.8)  # the first column is the clean one
        for position, (_, rows) in zip(x, columns, strict=True):
            if len(rows) > 1:
                top.plot([position + offset] * len(rows), [row["ap50"][name] for row in rows], ".", color="k", ms=3)
    for position, (_, rows) in zip(x, columns, strict=True):
        if "ap50" not in rows[0]:
            top.text(position, 0.02, "background only", ha="center", va="bottom", rotation=90, fontsize=7,
                     color="0.4")
    top.set_ylabel("AP50 (each frame on its own)")
    top.set_ylim(0, 1.25)
    top.set_yticks(np.linspace(0, 1, 6))
    top.legend(fontsize=8, loc="upper center", ncol=2)
    top.set_title(f"{report['scene']}: {report['frames']['count']} frames; dashed: clean AP50; COCO-C bars are the "
                  f"mean over severities {', '.join(map(str, report['severities']))} (dots)", fontsize=9)
    width = 0.8 / max(len(counts), 1)
    for index, key in enumerate(counts):
        values = [np.mean([row["false_people"][key] for row in rows]) if "false_people" in rows[0] else np.nan
                  for _, rows in columns]
        bottom.bar(x + (index - (len(counts) - 1) / 2) * width, values, width, label=key, color=f"C{index + 2}")
    bottom.set_ylabel("people reported on the empty background\n(truth: nobody)")
    bottom.legend(fontsize=8, loc="upper left")
    bottom.set_xticks(x, [name for name, _ in columns], rotation=60, ha="right", fontsize=8)
    families = [rows[0]["family"] for _, rows in columns]
    for axes in (top, bottom):
        for position in np.flatnonzero(np.array(families[1:]) != np.array(families[:-1])):
            axes.axvline(position + 0.5, color="0.6", linewidth=0.8, linestyle=":")
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


# ---------------------------------------------------------------------------------------------------- the command

@dataclass(frozen=True)
class RobustnessRequest:
    """One run's settings, as ``python -m benchmarks.robustness`` parses them (see its ``--help``)."""

    bundle: Path
    video: Path
    gt: Path
    frames: FrameRange | None = None
    background: Path | None = None
    external: Path | None = None
    external_size: int | None = None
    corruptions: list[str] | None = None  # None: the 15 common ones; empty: no COCO-C
    severities: list[int] = field(default_factory=lambda: list(SEVERITIES))
    conditions: list[str] | None = None  # None: every camera-life condition; empty: none
    nudge: int = NUDGE_PX
    roll: float = ROLL_DEG
    threads: int | None = None
    unfit: str = DEFAULT_UNFIT  # the runtime's setting for the people of an unfit frame (vc.deploy.runtime)
    out: Path = field(default_factory=lambda: results_folder("robustness"))
    quiet: bool = False


def _command(args: RobustnessRequest, frames: FrameRange) -> str:
    """The command that measures the same again, every setting spelled out (``frames``: those selected), paths as
    reports name them (:func:`benchmarks.display_path`)."""
    words = [display_path(args.bundle), "--video", display_path(args.video), "--gt", display_path(args.gt),
             "--frames", f"{frames.first}:{frames.last or ''}:{frames.step}"]
    if args.background is not None:
        words += ["--background", display_path(args.background)]
    if args.external is not None:
        words += ["--external", display_path(args.external)]
        words += ["--external-size", str(args.external_size)] if args.external_size else []
    if args.corruptions is not None:
        words += ["--corruptions", *args.corruptions]
    words += ["--severities", *map(str, sorted(set(args.severities)))]
    if args.conditions is not None:
        words += ["--conditions", *args.conditions]
    words += ["--nudge", str(args.nudge), "--roll", f"{args.roll:g}"]
    words += ["--threads", str(args.threads)] if args.threads else []
    words += ["--unfit", args.unfit]
    return "python -m benchmarks.robustness " + shlex.join(words + ["--out", display_path(args.out)])


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.robustness", description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path, help="a vc-export bundle (folder or zip)")
    parser.add_argument("--video", type=Path, required=True, help="video file or folder of frames")
    parser.add_argument("--gt", type=Path, required=True, help="ground-truth boxes, MOT text format")
    parser.add_argument("--frames", type=FrameRange.parse, default=None,
                        help="first:last:step, 1-based and inclusive (default: every annotated frame)")
    parser.add_argument("--background", type=Path, default=None,
                        help="the scene's empty background image: people reported on it under every condition")
    parser.add_argument("--external", type=Path, default=None, help="a YOLO-pose style ONNX model to compare with")
    parser.add_argument("--external-size", type=int, default=None, help="its square input size (if dynamic)")
    parser.add_argument("--corruptions", nargs="*", default=None, metavar="NAME",
                        help="COCO-C corruptions (default: the 15 common ones; none given: skip COCO-C)")
    parser.add_argument("--severities", type=int, nargs="+", default=list(SEVERITIES), choices=SEVERITIES,
                        help="COCO-C severities (default: 1 2 3 4 5)")
    parser.add_argument("--conditions", nargs="*", default=None, metavar="KEY",
                        help=f"camera-life conditions (default: all: {' '.join(camera_life_conditions())}; none "
                             "given: skip them)")
    parser.add_argument("--nudge", type=int, default=NUDGE_PX, help=f"pixels the camera is nudged (default "
                                                                    f"{NUDGE_PX})")
    parser.add_argument("--roll", type=float, default=ROLL_DEG,
                        help=f"degrees the camera is rolled about the frame's centre (default {ROLL_DEG:g})")
    parser.add_argument("--threads", type=int, default=None, help="threads per detector (default: all usable)")
    parser.add_argument("--unfit", choices=UNFIT_SETTINGS, default=DEFAULT_UNFIT,
                        help="the bundle's people on frames its scene fitness finds unfit: withheld, as shipped "
                             "(default), or kept, to measure the networks alone")
    parser.add_argument("--out", type=Path, default=results_folder("robustness"))
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def _conditions(args: RobustnessRequest) -> list[Condition]:
    camera_life = camera_life_conditions(args.nudge, args.roll)
    keys = list(camera_life) if args.conditions is None else args.conditions
    unknown = [key for key in keys if key not in camera_life]
    if unknown:
        raise InputError(None, "--conditions", f"unknown {', '.join(unknown)}; known: {', '.join(camera_life)}")
    corruptions = args.corruptions
    if corruptions is None or corruptions:
        names = imagecorruptions_module().get_corruption_names("common")
        corruptions = names if corruptions is None else corruptions
        unknown = [name for name in corruptions if name not in names]
        if unknown:
            raise InputError(None, "--corruptions", f"unknown {', '.join(unknown)}; COCO-C's: {', '.join(names)}")
    return ([clean_condition()] + [camera_life[key] for key in keys]
            + coco_c_conditions(corruptions, sorted(set(args.severities))))


def _frames(args: RobustnessRequest, truth: dict[int, np.ndarray], frame_size: tuple[int, int]) -> tuple[
        FrameRange, list[Frame]]:
    frames = args.frames or FrameRange(1, max(truth))
    source = FrameSource(args.video, frames)
    if (frames.last is None or frames.last > max(truth)) and source.count > frames.count(max(truth)):
        raise InputError(args.gt, "frames", f"the selection reaches past the last annotated frame ({max(truth)}); "
                                            f"select with --frames first:{max(truth)}:step")
    width, height = frame_size
    selected = list(source)
    for frame in selected:
        if frame.image.shape != (height, width, 3):
            raise InputError(args.video, f"frame {frame.number}", f"is {frame.image.shape[1]}x{frame.image.shape[0]}, "
                                                                  f"the bundle's camera is {width}x{height}")
    return frames, selected


def run(args: RobustnessRequest) -> dict:
    """Measure every condition and return the report (see the module's docstring)."""
    started = time.perf_counter()
    conditions = _conditions(args)
    truth = read_mot_boxes(args.gt)
    with Runtime(args.bundle, threads=args.threads, unfit=args.unfit) as runtime:
        bundle = runtime.bundle
        frames, selected = _frames(args, truth, bundle.frame_size)
        background = None
        if args.background is not None:
            background = read_frame_image(args.background)
            width, height = bundle.frame_size
            if background.shape != (height, width, 3):
                raise InputError(args.background, "", f"is {background.shape[1]}x{background.shape[0]}, the "
                                                      f"bundle's camera is {width}x{height}")
        if args.threads:
            cv2.setNumThreads(args.threads)
        detectors: dict[str, Callable[[np.ndarray], Detections]] = {
            OURS: BundleDetector(runtime)}
        external = None
        if args.external is not None:
            model = YoloPoseOnnx(args.external, args.external_size, args.threads)
            external = f"{args.external.name} @{model.size}"
            detectors[external] = model
        scored = sum(not condition.background_only for condition in conditions)
        total = scored * len(selected) + (len(conditions) if background is not None else 0)
        with tqdm(total=total, desc="robustness", unit="frame", disable=args.quiet) as progress:
            measurements = []
            for condition in conditions:
                progress.set_postfix_str(condition.key)
                runtime.reset()  # a registration is the camera's, not carried from one condition to the next
                measurements.append(measure(condition, selected, truth, background, detectors, progress))
    numbers = [frame.number for frame in selected]
    halves = positions_by_half(numbers, frames.first, frames.last or numbers[-1]) if numbers else {}
    summary = summarise(measurements, external, halves if all(halves.values()) else None)
    severities = sorted(set(args.severities))
    return {"benchmark": "robustness", "machine": cpu_facts()[0], "threads": args.threads or usable_cores(),
            "command": _command(args, frames), "bundle": _bundle_facts(args.bundle, bundle.manifest),
            "scene": bundle.manifest.get("scene"),
            "centre_thresholds": sorted({entry.decode.centre_threshold for entry in bundle.regions}),
            "video": display_path(args.video), "ground_truth": display_path(args.gt),
            "frames": {"first": frames.first, "last": frames.last, "step": frames.step, "count": len(selected)},
            "halves": {half: {"first": numbers[positions[0]], "last": numbers[positions[-1]],
                              "count": len(positions)} for half, positions in halves.items() if positions},
            "people": int(sum(len(truth.get(frame.number, ())) for frame in selected)),
            "background": None if args.background is None else display_path(args.background),
            "external": external, "detectors": list(detectors), "imagecorruptions": imagecorruptions_version(),
            "severities": severities, "tracking": "none: each frame on its own", "unfit": args.unfit,
            "seconds": round(time.perf_counter() - started, 1), **summary}


def _bundle_facts(path: Path, manifest: dict) -> dict:
    """What names a bundle beyond its folder's name: its scene, precision and models' digests."""
    regions = manifest.get("regions", [])
    return {"path": display_path(path), "scene": manifest.get("scene"),
            "scene_hash": str(manifest.get("scene_hash", ""))[:12] or None,
            "precision": sorted({region.get("precision") for region in regions if region.get("precision")}),
            "models_sha256": {region.get("name"): str(region.get("model_sha256", ""))[:12] for region in regions},
            "visual_compiler": manifest.get("versions", {}).get("visual-compiler")}


def report_lines(report: dict) -> list[str]:
    """The short summary printed at the end."""
    lines = [f"robustness: {report['frames']['count']} frames, {len(report['conditions'])} conditions, "
             f"{report['seconds']:.0f} s on {report['machine']}"]
    clean = next(row for row in report["conditions"] if row["family"] == CLEAN)
    for name in report["detectors"]:
        line = f"  {name}: clean AP50 {_fmt(clean.get('ap50', {}).get(name))}"
        for family, summary in report["families"].items():
            if "mPC" in summary:
                line += f"; {family} mPC {_fmt(summary['mPC'][name])} rPC {_fmt(summary['rPC'][name])}"
        lines.append(line)
    for half, frames in report.get("halves", {}).items():
        if "ap50_by_half" in clean:
            lines.append(f"  {half} half, frames {frames['first']}-{frames['last']}: clean AP50 "
                         + ", ".join(f"{name} {_fmt(clean['ap50_by_half'][half][name])}"
                                     for name in report["detectors"])
                         + "".join(f"; {family} rPC " + ", ".join(_fmt(summary["by_half"][half]["rPC"][name])
                                                                  for name in report["detectors"])
                                   for family, summary in report["families"].items() if "by_half" in summary))
    for family, summary in report["families"].items():
        if "false_people_per_frame" in summary:
            lines.append(f"  false people per frame on the background, {family}: "
                         + ", ".join(f"{key} {value:.2f}" for key, value in summary["false_people_per_frame"].items()))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = RobustnessRequest(**vars(parser.parse_args(argv)))
    try:
        report = run(args)
    except InputError as error:
        parser.error(str(error))
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "robustness.json", report)
    (args.out / "robustness.md").write_text(markdown(report))
    plot(report, args.out / "robustness.png")
    print("\n".join(report_lines(report) + [f"  -> {args.out}"]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
