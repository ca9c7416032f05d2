"""``vc-render``: synthetic people rendered into a scene's regions, with exact labels.

    vc-render SCENE -o OUT --samples N [--regions R ...] [--spp S] [--seed K] [--shard-size M] [--max-people P]
              [--processes W] [--quiet]
    vc-render SCENE --preview -o sheet.png [--samples N] [--regions R ...] [--spp S] [--seed K]

The dataset goes to ``OUT/<region>/shard-NNNNN/`` with ``OUT/manifest.json`` and ``OUT/render_summary.json``
(see :mod:`vc.render.dataset`). Re-running the same command completes missing shards and never rewrites a
finished one. ``--processes W`` renders the shards in W worker processes of this machine (for a GPU or many
cores; the same bytes, see :mod:`vc.stages.executors`). ``--preview`` renders a few samples (the same ones the
dataset would hold) into a contact sheet with boxes, skeletons and masks drawn. Bad input prints one ``error:``
line and exits with status 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors, non_negative_int, positive_int
from vc.errors import InputError
from vc.render.job import DEFAULT_SHARD_SIZE
from vc.render.synthesis import SynthesisSettings
from vc.stages.config import RenderSettings
from vc.stages.executors import LocalProcesses
from vc.stages.render import RenderJob, describe_plan, prepare_render

PREVIEW_SAMPLES = 9


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-render", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("scene", type=Path, help="scene YAML")
    parser.add_argument("-o", "--output", type=Path, required=True,
                        help="dataset folder (or the PNG contact sheet with --preview)")
    parser.add_argument("--samples", type=positive_int, help="samples per region (preview: in all)")
    parser.add_argument("--regions", nargs="+", metavar="R", help="render only these regions (default: all)")
    parser.add_argument("--spp", type=positive_int, default=SynthesisSettings.spp,
                        help=f"samples per pixel (default {SynthesisSettings.spp})")
    parser.add_argument("--seed", type=non_negative_int, default=SynthesisSettings.seed,
                        help=f"dataset seed (default {SynthesisSettings.seed})")
    parser.add_argument("--shard-size", type=positive_int, default=DEFAULT_SHARD_SIZE,
                        help=f"samples per shard (default {DEFAULT_SHARD_SIZE})")
    parser.add_argument("--max-people", type=non_negative_int,
                        help="most people per sample (default: from each region's ground area, 2 to 6)")
    parser.add_argument("--processes", type=positive_int, metavar="W",
                        help="render the shards in W worker processes (default: in this process)")
    parser.add_argument("--preview", action="store_true", help="write a contact sheet instead of a dataset")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def report_job(job: RenderJob) -> None:
    """What is about to be rendered, and under which light and effects."""
    settings = job.settings
    print(f"scene  {job.scene.name}  regions {', '.join(region.name for region in job.regions)}  spp "
          f"{settings.spp}  seed {settings.seed}")
    for line in describe_plan(job.plan):
        print(line)


def report_summary(summary: dict, output: Path) -> None:
    for name, counts in summary["dataset"].items():
        now = summary["rendered_now"].get(name)
        spent = "renderer-seconds" if summary.get("executor") else "s"  # summed over the workers
        made = f"{now['samples']} rendered now in {now['seconds']:.1f} {spent}" if now else "already complete"
        print(f"  {name:<6} {counts['samples']} samples, {counts['people']} people  ({made})")
    rate = summary["samples_per_second"]
    print(f"done   {summary['seconds']:.1f} s" + (f", {rate:.1f} samples/s" if rate else "")
          + f", {summary['skipped_shards']} finished shards kept  -> {output}")


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.samples is None and not args.preview:
        raise InputError(args.output, "--samples", "how many samples per region? (--samples N, N >= 1)")
    if args.preview and args.processes:
        raise InputError(args.output, "--processes", "a preview renders in this process; drop --processes")
    samples = args.samples or PREVIEW_SAMPLES
    settings = RenderSettings(samples=samples, spp=args.spp, seed=args.seed, max_people=args.max_people,
                              shard_size=args.shard_size)
    job = prepare_render(args.scene, settings, args.regions)
    report_job(job)
    if args.preview:
        job.preview(args.output, samples)
        print(f"preview  {samples} samples of {len(job.regions)} regions -> {args.output}")
        return 0
    executor = LocalProcesses(args.processes) if args.processes else None
    report_summary(job.run(args.output, show_progress=not args.quiet, executor=executor), args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
