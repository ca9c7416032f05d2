"""``vc-eval``: a bundle on real video frames against ground-truth boxes, beside detectors trained on real photos.

    vc-eval BUNDLE --video V --gt GT.txt -o OUT [--frames first:last:step] [--no-hog] [--hog-upscale F]
            [--external MODEL.onnx [--external-name NAME]]... [--external-size S] [--threads N]
            [--fps F] [--no-tracking] [--unfit suppress|flag] [--engine onnxruntime|openvino] [--quiet]

For every selected frame each detector runs and is timed: the bundle (through :mod:`vc.deploy.runtime`, as the
appliance runs it), OpenCV's HOG people detector, and optionally any YOLO-pose style ONNX model
(:mod:`vc.evaluation.real_video`). The bundle's people are tracked over every frame of the selected span (a
video's frame rate is read from it; give ``--fps`` for a folder of frames), and their walking direction decides
which way they face where the network cannot tell (:mod:`vc.deploy.tracking`). Writes
``OUT/metrics.json`` (AP50, milliseconds per frame, for the bundle its operating point and recall by person
height, group and region, and the scored frames per scene fitness state: :mod:`vc.deploy.fitness`; an unfit
frame's people are withheld, or with ``--unfit flag`` kept), ``OUT/precision_recall.png``,
``OUT/contact_sheet.png`` (frames with the bundle's people in colour and the ground truth in white),
``OUT/detections.jsonl``, and the bundle's miss analysis (:mod:`vc.evaluation.misses`): ``OUT/misses.json`` (near
misses and misses, the near misses' box errors, false positives by kind, every error listed), ``OUT/misses.png``
and ``OUT/worst_frames.png`` (the frames of most errors: truth white when found, orange near missed, red missed;
false positives magenta).

GT is in the MOT text format; only frames inside its annotated range can be selected (a frame without a line
there has nobody in it). Bad input exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc import __version__
from vc.cli.common import fitness_line, handles_input_errors, positive_float, positive_int
from vc.deploy.engines import DEFAULT_ENGINE, ENGINES
from vc.deploy.frames import FrameRange
from vc.deploy.runtime import DEFAULT_UNFIT, UNFIT_SETTINGS
from vc.deploy.tracking import TrackingConfig
from vc.errors import InputError
from vc.evaluation.misses import MissAnalysis
from vc.evaluation.real_video import (
    HOG_UPSCALE,
    OURS,
    EvaluationReport,
    EvaluationRequest,
    ExternalModel,
    evaluate_bundle,
)


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
    parser.add_argument("--hog-upscale", type=float, default=HOG_UPSCALE,
                        help=f"HOG runs on the frame upscaled this much (default {HOG_UPSCALE})")
    parser.add_argument("--external", type=Path, action="append", default=[],
                        help="a YOLO-pose style ONNX model to compare with (repeatable); the first is the reference "
                             "the bundle's pose is compared with, a second shows the comparison's ceiling")
    parser.add_argument("--external-size", type=positive_int, help="their square input size (if dynamic)")
    parser.add_argument("--external-name", action="append", default=[],
                        help="a label per --external, in order (default: the file name and input size)")
    parser.add_argument("--threads", type=positive_int, default=None, help="threads per detector (default: all)")
    parser.add_argument("--fps", type=positive_float, default=None,
                        help="the input's frames per second, for tracking (default: a video's own rate; a folder of "
                             "frames is tracked only when given)")
    parser.add_argument("--no-tracking", action="store_true",
                        help="each frame on its own: no tracks, facing from appearance only")
    parser.add_argument("--unfit", choices=UNFIT_SETTINGS, default=DEFAULT_UNFIT,
                        help="the bundle's people on a frame the scene fitness finds unfit: withheld (suppress, the "
                             "default, as vc-run) or kept (flag); a covered frame never yields people")
    parser.add_argument("--engine", choices=ENGINES, default=DEFAULT_ENGINE,
                        help=f"what runs the bundle's networks (default {DEFAULT_ENGINE}; openvino: OpenVINO's CPU "
                             "plugin)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def _request(args: argparse.Namespace) -> EvaluationRequest:
    if len(args.external_name) > len(args.external):
        raise InputError(None, "--external-name", f"{len(args.external_name)} names for {len(args.external)} models")
    names = args.external_name + [None] * (len(args.external) - len(args.external_name))
    return EvaluationRequest(bundle=args.bundle, video=args.video, ground_truth=args.gt, output=args.output,
                             frames=args.frames, hog=not args.no_hog, hog_upscale=args.hog_upscale,
                             externals=tuple(ExternalModel(path, name) for path, name in zip(args.external, names,
                                                                                           strict=True)),
                             external_size=args.external_size, threads=args.threads,
                             tracking=None if args.no_tracking else TrackingConfig(), fps=args.fps,
                             unfit=args.unfit, engine=args.engine)


def _rates(rates: dict) -> str:
    return ", ".join(f"{label} {value['recall']:.2f} ({value['people']})" for label, value in rates.items())


def _miss_summary(misses: MissAnalysis) -> str:
    outcomes, kinds, near = misses.outcomes(), misses.false_positive_kinds(), misses.near_miss_errors()
    lines = [f"  at score >= {misses.score_threshold:.3f}: precision {misses.precision:.3f}, recall "
             f"{misses.recall:.3f}; not found {outcomes['near miss'] + outcomes['missed']}: {outcomes['near miss']} "
             f"near misses, {outcomes['missed']} with nothing near",
             f"  recall by height: {_rates(misses.recall_by_height())}",
             f"  by overlap: {_rates(misses.recall_by_group())}; by region: {_rates(misses.recall_by_region())}",
             *([f"  by the frame's edge: {_rates(edge)}"] if (edge := misses.recall_by_edge()) else []),
             "  false positives: " + ", ".join(f"{count} {kind}" for kind, count in kinds.items())]
    if near["width_ratio"] is not None:
        lines.append(f"  near misses: width x{near['width_ratio']['median']:.2f}, height "
                     f"x{near['height_ratio']['median']:.2f}, |offset| {near['abs_x_offset']['median']:.2f} widths; "
                     f"{near['neighbour_box']} were a neighbour's box")
    return "\n".join(lines)


def _arrivals_summary(summary: dict) -> str:
    def kind(label: str, entry: dict) -> str:
        within = f", within {entry['found_within']['seconds']:g} s {entry['found_within']['people']}" \
            if "found_within" in entry else ""
        return (f"{entry['people']} {label}: found in their first frame {entry['found_in_first_frame']}{within}, "
                f"never {entry['never_found']}")
    kinds = [kind(label, entry) for label, entry in summary.items() if entry["people"]]
    return "  people coming into view: " + ("; ".join(kinds) if kinds else "none while scored")


def report(result: EvaluationReport, output: Path) -> None:
    print(f"vc-eval: {result.frames} frames of {result.video.name}, {result.evaluations[OURS].ground_truth} people -> "
          f"{output}")
    for name, summary in result.metrics["detectors"].items():
        print(f"  {name:32s} AP50 {summary['ap50']:.3f} ({summary['ap50_in_annotated_area']:.3f} in the annotated "
              f"area)   {summary['ms_per_frame']['median']:8.1f} ms/frame")
    if result.misses is not None:
        print(_miss_summary(result.misses))
        print(_arrivals_summary(result.metrics["arrivals"]["summary"]))
    tracking = result.metrics["tracking"]
    if "fps" not in tracking:
        print(f"  not tracked: {tracking['off']}")
    else:
        accuracy = tracking.get("accuracy")
        print(f"  tracked at {tracking['fps']:g} frames/s" + ("" if accuracy is None or accuracy["mota"] is None else
              f": MOTA {accuracy['mota']:.3f}, IDF1 {accuracy['idf1']:.3f}, {accuracy['id_switches']} identity "
              f"switches over the scored frames"))
    print(fitness_line(result.metrics["fitness"]))
    for reference, by_name in result.agreements.items():
        for name, agreement in by_name.items():
            overall = "n/a" if agreement.overall is None else f"{agreement.overall:.3f}"
            matched = agreement.overall_if_left_right_matched
            print(f"  pose agreement with {reference}: {name} {overall} ({agreement.people} people)"
                  + ("" if matched is None else f"; left and right the other way round for "
                                                f"{agreement.left_right_swapped}, {matched:.3f} were they matched"))


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    report(evaluate_bundle(_request(args), show_progress=not args.quiet), args.output)
    return 0
