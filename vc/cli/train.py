"""``vc-train``: one ScenePoseNet per region, trained on a ``vc-render`` dataset only.

    vc-train DATASET -o RUN [--region R ... | --all] [--arch A] [--width W] [--sb-units N] [--steps N]
             [--batch-size B] [--seed K]

Writes ``RUN/checkpoints/<region>.pt`` (resumable: run the same command again after an interruption),
``RUN/metrics.json`` (held-out synthetic AP50, PCKh@0.5 overall and per keypoint, mask IoU, training speed, per
region), ``RUN/precision_recall.png`` and, per region, ``RUN/<region>/{precision_recall,training_loss}.png``.
A scene planned with ``regions: {mode: single}`` has one region for its whole walkable area: training it is the
paper's SPN-G. Bad input prints one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors, non_negative_int, positive_int
from vc.deploy.metrics import Evaluation
from vc.errors import InputError
from vc.io import write_json
from vc.model.config import DEFAULT_ARCH, PRESETS, network_config
from vc.model.data import open_region
from vc.model.train import RegionResult, RegionTrainer, TrainConfig, for_network, select_device
from vc.plots import plot_precision_recall
from vc.render.dataset import read_manifest

METRICS = "metrics.json"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-train", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("dataset", type=Path, help="a vc-render dataset folder")
    parser.add_argument("-o", "--output", type=Path, required=True, help="run folder (checkpoints, metrics)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--region", nargs="+", metavar="R", help="train only these regions")
    which.add_argument("--all", action="store_true", help="train every region of the dataset (the default)")
    parser.add_argument("--arch", choices=sorted(PRESETS), default=DEFAULT_ARCH,
                        help=f"network preset (default {DEFAULT_ARCH})")
    parser.add_argument("--width", type=positive_int, help="override the preset's channel width")
    parser.add_argument("--sb-units", type=positive_int, help="override the preset's number of SB units")
    defaults = TrainConfig()
    parser.add_argument("--steps", type=positive_int, default=defaults.steps,
                        help=f"optimiser steps per region (default {defaults.steps})")
    parser.add_argument("--batch-size", type=positive_int, default=defaults.batch_size,
                        help=f"images per step (default {defaults.batch_size})")
    parser.add_argument("--seed", type=int, default=defaults.seed, help="seed of weights and data order")
    parser.add_argument("--workers", type=non_negative_int, default=1, help="data-loading processes (default 1)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


def _regions(dataset: Path, names: list[str] | None) -> list[str]:
    available = list(read_manifest(dataset).get("regions", {}))
    if not names:
        return available
    unknown = [name for name in names if name not in available]
    if unknown:
        raise InputError(dataset / "manifest.json", "regions", f"region {', '.join(unknown)} is not in this dataset "
                                                               f"(it has {', '.join(available) or 'none'})")
    return list(dict.fromkeys(names))


def _merged_metrics(run: Path, manifest: dict, dataset: Path, device: str, results: list[RegionResult]) -> dict:
    """Regions trained by earlier invocations into the same run stay in ``metrics.json``."""
    previous = {}
    if (run / METRICS).is_file():
        try:
            previous = json.loads((run / METRICS).read_text()).get("regions", {})
        except (OSError, json.JSONDecodeError):
            previous = {}
    regions = {**previous, **{result.region: result.to_dict() for result in results}}
    return {"scene": manifest["scene"], "scene_hash": manifest["scene_hash"], "dataset": str(dataset),
            "device": device, "regions": dict(sorted(regions.items()))}


def _summary(results: list[RegionResult]) -> str:
    lines = [f"{'region':8} {'AP50':>6} {'PCKh':>6} {'maskIoU':>8} {'people':>7} {'steps':>6} {'min':>6} {'img/s':>6}"]
    for result in results:
        evaluation: Evaluation = result.evaluation.evaluation
        lines.append(f"{result.region:8} {evaluation.ap50:6.3f} {evaluation.pckh or 0:6.3f} "
                     f"{evaluation.mask_iou or 0:8.3f} {evaluation.ground_truth:7d} {result.steps:6d} "
                     f"{result.train_seconds / 60:6.1f} {result.images_per_second:6.1f}")
    return "\n".join(lines)


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    regions = _regions(args.dataset, args.region)
    network = network_config(args.arch)
    overrides = {"width": args.width, "sb_units": args.sb_units}
    if any(value is not None for value in overrides.values()):
        try:
            network = replace(network, **{key: value for key, value in overrides.items() if value is not None})
        except ValueError as error:
            raise InputError(None, "--width/--sb-units", str(error)) from None
    config = for_network(network, steps=args.steps, batch_size=args.batch_size, seed=args.seed)
    device = select_device()
    print(f"vc-train: {len(regions)} region(s) of {args.dataset}, {network.name} network, {config.steps} steps of "
          f"{config.batch_size}, on {device.type}")
    results = []
    for name in regions:
        data = open_region(args.dataset, name, config.held_out_fraction)
        trainer = RegionTrainer(data, config, args.output, args.dataset, device, args.workers,
                                show_progress=not args.quiet)
        trainer.train()
        results.append(trainer.evaluate())
    manifest = read_manifest(args.dataset)
    write_json(args.output / METRICS, _merged_metrics(args.output, manifest, args.dataset, device.type, results))
    plot_precision_recall({r.region: r.evaluation.evaluation for r in results}, args.output / "precision_recall.png",
                          f"{manifest['scene']}: held-out synthetic")
    print(_summary(results))
    print(f"checkpoints in {args.output / 'checkpoints'}, metrics in {args.output / METRICS}")
    return 0
