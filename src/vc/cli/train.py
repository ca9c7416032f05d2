"""``vc-train``: one ScenePoseNet per region, trained on a ``vc-render`` dataset only.

    vc-train DATASET -o RUN [--region R ... | --all] [--arch A] [--width W] [--sb-units N] [--steps N]
             [--batch-size B] [--seed K] [--centre-offsets [--offset-weight W]]
             [--crop-pose | --no-crop-pose]

Writes ``RUN/checkpoints/<region>.pt`` (resumable: run the same command again after an interruption),
``RUN/metrics.json`` (held-out synthetic AP50, PCKh@0.5 overall and per keypoint, mask IoU, recall of people
overlapping another, training speed, per region), ``RUN/precision_recall.png`` and, per region,
``RUN/<region>/{precision_recall,training_loss}.png``, and the facing and keypoint models with what they measured,
``RUN/facing.{onnx,json}`` (:mod:`vc.model.facing`) and ``RUN/crop_pose.{onnx,json}`` (:mod:`vc.model.crop_pose`:
by default where most of the scene's people are tall enough for it; ``--crop-pose`` always, ``--no-crop-pose``
never).
A scene planned with ``regions: {mode: single}`` has one region for its whole walkable area: training it is the
paper's SPN-G. Bad input prints one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors, non_negative_int, positive_float, positive_int
from vc.evaluation.metrics import Evaluation
from vc.model.config import PRESETS
from vc.model.crop_pose import CROP_POSE_MODEL
from vc.model.facing import FACING_MODEL
from vc.model.trainer import RegionResult
from vc.stages.config import TrainSettings, train_settings
from vc.stages.train import METRICS, TrainingJob, prepare_training, read_metrics


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-train", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("dataset", type=Path, help="a vc-render dataset folder")
    parser.add_argument("-o", "--output", type=Path, required=True, help="run folder (checkpoints, metrics)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--region", nargs="+", metavar="R", help="train only these regions")
    which.add_argument("--all", action="store_true", help="train every region of the dataset (the default)")
    defaults = TrainSettings()
    parser.add_argument("--arch", choices=sorted(PRESETS), default=defaults.arch,
                        help=f"network preset (default {defaults.arch})")
    parser.add_argument("--width", type=positive_int, help="override the preset's channel width")
    parser.add_argument("--sb-units", type=positive_int, help="override the preset's number of SB units")
    parser.add_argument("--steps", type=positive_int, default=defaults.steps,
                        help=f"optimiser steps per region (default {defaults.steps})")
    parser.add_argument("--batch-size", type=positive_int, default=defaults.batch_size,
                        help=f"images per step (default {defaults.batch_size})")
    parser.add_argument("--seed", type=int, default=defaults.seed, help="seed of weights and data order")
    parser.add_argument("--workers", type=_workers, default=defaults.workers, metavar="N|auto",
                        help=f"{TrainSettings.model_fields['workers'].description} (default {defaults.workers})")
    parser.add_argument("--centre-offsets", action="store_true",
                        help=TrainSettings.model_fields["centre_offsets"].description)
    parser.add_argument("--fine-centre", action="store_true",
                        help=TrainSettings.model_fields["fine_centre"].description)
    parser.add_argument("--head-map", action="store_true", help=TrainSettings.model_fields["head_map"].description)
    parser.add_argument("--crop-pose", action=argparse.BooleanOptionalAction, default=defaults.crop_pose,
                        help=TrainSettings.model_fields["crop_pose"].description + f" (default {defaults.crop_pose})")
    parser.add_argument("--offset-weight", type=positive_float, default=defaults.centre_offset_weight,
                        metavar="W", help=TrainSettings.model_fields["centre_offset_weight"].description
                        + f" (default {defaults.centre_offset_weight:g})")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


def _workers(value: str) -> int | str:
    return value if value == "auto" else non_negative_int(value)


def report_job(job: TrainingJob) -> None:
    print(f"vc-train: {len(job.regions)} region(s) of {job.dataset}, {job.config.network.name} network, "
          f"{job.config.steps} steps of {job.config.batch_size}, on {job.device.type} in "
          f"{'bf16' if job.config.bf16_autocast else 'fp32'}{' channels-last' if job.config.channels_last else ''}, "
          f"{job.workers} data loader(s)")
    print("\n".join(job.camera_range_plan()))


def report_results(results: list[RegionResult], run: Path) -> None:
    lines = [f"{'region':8} {'AP50':>6} {'PCKh':>6} {'maskIoU':>8} {'people':>7} {'grouped':>12} {'steps':>6} "
             f"{'min':>6} {'img/s':>6}"]
    for result in results:
        evaluation: Evaluation = result.evaluation.evaluation
        grouped = (f"{evaluation.recall_overlapping:.3f} of {evaluation.overlapping}"
                   if evaluation.recall_overlapping is not None else "none")
        lines.append(f"{result.region:8} {evaluation.ap50:6.3f} {evaluation.pckh or 0:6.3f} "
                     f"{evaluation.mask_iou or 0:8.3f} {evaluation.ground_truth:7d} {grouped:>12} {result.steps:6d} "
                     f"{result.train_seconds / 60:6.1f} {result.images_per_second:6.1f}")
    print("\n".join(lines))
    facing = read_metrics(run).get("facing") if (run / METRICS).is_file() else None
    if facing is not None:
        print(f"facing model: {_facing_line(facing)}" + ("" if "skipped" in facing else f" -> {run / FACING_MODEL}"))
    crop_pose = read_metrics(run).get("crop_pose") if (run / METRICS).is_file() else None
    if crop_pose is not None:
        print(f"keypoint model: {_crop_pose_line(crop_pose)}"
              + ("" if "skipped" in crop_pose else f" -> {run / CROP_POSE_MODEL}"))
    print(f"checkpoints in {run / 'checkpoints'}, metrics in {run / METRICS}")


def _facing_line(facing: dict) -> str:
    """What the run's facing model measured (vc.model.facing), or why it has none."""
    if "skipped" in facing:
        return f"none: {facing['skipped']}"
    accuracy = facing["held_out_accuracy"]
    measured = (f"{accuracy:.3f} of {facing['held_out_crops']} held-out people read facing the right way"
                if accuracy is not None else "no held-out people to measure it on")
    turn = facing.get("face_turn", {})
    turned = ""
    if "skipped" in turn:
        turned = f"; face turn none: {turn['skipped']}"
    elif turn.get("held_out_profile_sign") is not None:
        turned = (f"; face turn {turn['held_out_profile_sign']:.3f} of held-out profiles read pointing the right way "
                  f"(mean error {turn['held_out_error']:.3f})")
    head = facing.get("head_colours", {})
    headed = (f"; head's colours AUC {head['held_out_auc']:.3f} on held-out people"
              if head.get("held_out_auc") is not None else "")
    return f"{measured} ({facing['train_crops']} trained on){turned}{headed}"


def _crop_pose_line(crop_pose: dict) -> str:
    """What the run's keypoint model measured (vc.model.crop_pose), or why it has none."""
    if "skipped" in crop_pose:
        return f"none: {crop_pose['skipped']}"
    pckh = crop_pose["held_out_pckh"]
    measured = (f"PCKh {pckh:.3f} on {crop_pose['held_out_crops']} held-out people" if pckh is not None
                else "no held-out people to measure it on")
    shipped = f"; ships at {crop_pose['precision']}" if "precision" in crop_pose else ""
    return f"{measured} ({crop_pose['train_crops']} trained on){shipped}"


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    settings = train_settings(arch=args.arch, width=args.width, sb_units=args.sb_units, steps=args.steps,
                              batch_size=args.batch_size, seed=args.seed, workers=args.workers,
                              centre_offsets=args.centre_offsets, fine_centre=args.fine_centre,
                              head_map=args.head_map,
                              crop_pose=args.crop_pose, centre_offset_weight=args.offset_weight)
    job = prepare_training(args.dataset, settings, args.region)
    report_job(job)
    report_results(job.run(args.output, show_progress=not args.quiet), args.output)
    return 0
