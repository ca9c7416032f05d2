"""``vc-compile``: a scene description in, a tested ONNX bundle out — every stage in one command.

    vc-compile SCENE [SCENE ...] -o OUT [--budget quick|standard|full | --config FILE]
               [--set section.field=value ...] [--seed K] [--quiet]
               [--executor in-process | processes [--processes N] | ray [--address ADDR]]

Stages: check (validate the scene, plan its regions) -> render (``OUT/renders``) -> train (``OUT/run``) -> export
(``OUT/bundle``, precision ``auto``: int8 where it holds on held-out renders) -> self-test (the bundle through the
runtime on full frames composed of held-out renders on the scene's background: AP50, ms/frame, false alarms on
the empty background; ``OUT/overlay.png``). A budget is a preset of one compile config
(:mod:`vc.stages.config`); ``OUT/compile_config.yaml`` holds the config the compile ran with, and ``--config`` reads
such a file back. ``OUT/compile.json`` records each finished stage; running the same command again skips those and
resumes the interrupted one where it stopped (render shards and training checkpoints are kept). Prints one summary
at the end: time per stage, held-out synthetic accuracy, bundle size, runtime ms/frame. Bad input exits with
status 2.

Several scenes compile into ``OUT/<scene name>`` each. ``--executor ray`` fans the render shards and the regions'
training out over a Ray cluster (``--address``: one to join; without it a local one on this machine), every
scene at once. ``--executor processes`` renders the shards in worker processes of this machine, for a GPU or
many cores that one renderer cannot keep busy; the regions then train in turn, and scenes compile one after
another. The datasets are byte-identical to an in-process compile's (:mod:`vc.stages.executors`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc import __version__
from vc.cli import export as export_cli
from vc.cli import render as render_cli
from vc.cli import train as train_cli
from vc.cli.common import handles_input_errors, non_negative_int, positive_int
from vc.model.trainer import RegionResult
from vc.stages.compile import SCENES_IN_FLIGHT, Reporter, compile_scene, compile_scenes, scene_outputs
from vc.stages.config import DEFAULT_PRESET, PRESETS, CompileConfig, read_config, with_overrides
from vc.stages.executors import EXECUTORS, make_executor
from vc.stages.export import ExportResult
from vc.stages.render import RenderJob
from vc.stages.train import TrainingJob


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-compile", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("scene", type=Path, nargs="+", help="scene YAML (several: each into OUT/<scene name>)")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--budget", choices=list(PRESETS), help="quick (~10 min, demo quality), standard (the "
                                                               "default) or full")
    which.add_argument("--config", type=Path, metavar="FILE",
                       help="a compile config (YAML, as OUT/compile_config.yaml is written)")
    parser.add_argument("--set", action="append", default=[], metavar="SECTION.FIELD=VALUE",
                        help="change one field of the config, e.g. train.steps=400 (repeatable)")
    parser.add_argument("--seed", type=non_negative_int, help="seed of the renders and the training")
    parser.add_argument("--executor", choices=list(EXECUTORS), default="in-process",
                        help="where render shards and regions' training run (default: this process)")
    parser.add_argument("--processes", type=positive_int, default=None,
                        help="worker processes of --executor processes (default: one per usable core)")
    parser.add_argument("--address", default=None, help="the Ray cluster to join (auto, HOST:PORT, ray://HOST:PORT); "
                                                        "default: start a local one")
    parser.add_argument("--scenes-at-once", type=positive_int, default=SCENES_IN_FLIGHT,
                        help=f"scenes compiled at once on a cluster (default {SCENES_IN_FLIGHT}; about its CPUs / 3 "
                             "keeps it busy)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


def config_from(args: argparse.Namespace) -> CompileConfig:
    """The config the arguments ask for: a budget's or a file's, then ``--set`` fields, then ``--seed``."""
    config = read_config(args.config) if args.config else PRESETS[args.budget or DEFAULT_PRESET]
    config = with_overrides(config, args.set)
    return config if args.seed is None else config.with_seed(args.seed)


class _Printer(Reporter):
    """The compile told as the single commands tell their stages."""

    def stage_started(self, name: str) -> None:
        print(f"== {name}")

    def stage_skipped(self, name: str, record: dict) -> None:
        print(f"== {name}: done before ({record['seconds']:.0f} s), skipped")

    def settings_changed(self, state_path: Path) -> None:
        print(f"vc-compile: settings differ from {state_path}'s; every stage runs again (kept work is reused "
              "where it still fits)")

    def rendering(self, job: RenderJob) -> None:
        render_cli.report_job(job)

    def rendered(self, summary: dict, output: Path) -> None:
        render_cli.report_summary(summary, output)

    def training(self, job: TrainingJob) -> None:
        train_cli.report_job(job)

    def trained(self, results: list[RegionResult], run: Path) -> None:
        train_cli.report_results(results, run)

    def exported(self, result: ExportResult, bundle: Path) -> None:
        export_cli.report_result(result, bundle)


def _summary(state: dict, out: Path) -> str:
    stages = state["stages"]
    lines = ["", "vc-compile summary",
             "  stage       seconds (of the run that did the stage; a resumed stage counts from its resume)"]
    lines += [f"  {name:<10} {record['seconds']:8.0f}" for name, record in stages.items()]
    lines.append(f"  total      {sum(record['seconds'] for record in stages.values()):8.0f}")
    for name, accuracy in stages["train"]["held_out"].items():
        grouped = accuracy.get("recall_overlapping")  # absent from older compiles' records, which resume without it
        lines.append(f"  {name}: held-out synthetic AP50 {accuracy['ap50']:.3f}, PCKh@0.5 {accuracy['pckh'] or 0:.3f}, "
                     f"mask IoU {accuracy['mask_iou'] or 0:.3f}, "
                     + (f"recall of people overlapping another {grouped:.3f}, " if grouped is not None else "")
                     + stages["export"]["precision"][name])
    test = stages["self-test"]
    lines.append(f"  bundle {stages['export']['bundle_bytes'] / 1e6:.2f} MB -> {out / 'bundle'}")
    lines.append(f"  self-test on {test['frames']} composed full frames: AP50 {test['ap50']:.3f}, "
                 f"{test['ms_per_frame']:.1f} ms/frame, {test['false_alarms_on_background']} false alarm(s) on the "
                 f"empty background -> {out / 'overlay.png'}")
    return "\n".join(lines)


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    config, executor = config_from(args), make_executor(args.executor, args.address, args.processes)
    if len(args.scene) == 1:
        state = compile_scene(args.scene[0], args.output, config, show_progress=not args.quiet, reporter=_Printer(),
                              executor=executor)
        print(_summary(state, args.output))
        return 0
    outputs = scene_outputs(args.scene, args.output)
    print(f"vc-compile: {len(outputs)} scenes on {executor.name} into {args.output}/<scene name>")
    compile_scenes(args.scene, args.output, config, executor,
                   on_done=lambda path, state: print(_summary(state, outputs[path]).replace(
                       "vc-compile summary", f"vc-compile summary: {path}"), flush=True), in_flight=args.scenes_at_once)
    return 0
