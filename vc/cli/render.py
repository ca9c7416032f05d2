"""``vc-render``: synthetic people rendered into a scene's regions, with exact labels.

    vc-render SCENE -o OUT --samples N [--regions R ...] [--spp S] [--seed K] [--shard-size M] [--max-people P]
              [--quiet]
    vc-render SCENE --preview -o sheet.png [--samples N] [--regions R ...] [--spp S] [--seed K]

The dataset goes to ``OUT/<region>/shard-NNNNN/`` with ``OUT/manifest.json`` and ``OUT/render_summary.json``
(see :mod:`vc.render.dataset`). Re-running the same command completes missing shards and never rewrites a
finished one. ``--preview`` renders a few samples (the same ones the dataset would hold) into a contact sheet
with boxes, skeletons and masks drawn. Bad input prints one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors, non_negative_int, positive_int
from vc.errors import InputError
from vc.io import write_image
from vc.render.plan import RenderPlan, plan_render
from vc.render.synthesis import SynthesisSettings
from vc.scenes.loader import Scene, load_scene
from vc.scenes.regions import Region, plan_regions

PREVIEW_SAMPLES = 9


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-render", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("scene", type=Path, help="scene YAML")
    parser.add_argument("-o", "--output", type=Path, required=True,
                        help="dataset folder (or the PNG contact sheet with --preview)")
    parser.add_argument("--samples", type=positive_int, help="samples per region (preview: in all)")
    parser.add_argument("--regions", nargs="+", metavar="R", help="render only these regions (default: all)")
    parser.add_argument("--spp", type=positive_int, default=16, help="samples per pixel (default 16)")
    parser.add_argument("--seed", type=non_negative_int, default=0, help="dataset seed (default 0)")
    parser.add_argument("--shard-size", type=positive_int, default=100, help="samples per shard (default 100)")
    parser.add_argument("--max-people", type=non_negative_int,
                        help="most people per sample (default: from each region's ground area, 2 to 6)")
    parser.add_argument("--preview", action="store_true", help="write a contact sheet instead of a dataset")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def _selected_regions(scene: Scene, regions: list[Region], names: list[str] | None) -> list[Region]:
    if not names:
        return regions
    known = {region.name: region for region in regions}
    unknown = [name for name in names if name not in known]
    if unknown:
        raise InputError(scene.path, "--regions", f"unknown region {', '.join(unknown)} (the scene plans "
                                                  f"{', '.join(known)})")
    return [known[name] for name in dict.fromkeys(names)]


def _writable_folder(path: Path) -> None:
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(path, "-o", f"cannot create the output folder ({error.strerror})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(path, "-o", "the output folder is not writable")


def _short(parameters: dict) -> str:
    """An effect's parameters on one line (nested per-region values left to the manifest)."""
    return ", ".join(f"{key} {value}" for key, value in parameters.items() if not isinstance(value, dict | list))


def print_plan(plan: RenderPlan) -> None:
    """The light and the effects plan: each effect on/off, why, its parameters and its cost per sample."""
    lighting = plan.lighting
    print(f"light  {lighting.summary()}")
    if lighting.estimate is not None:
        print(f"       {lighting.estimate.reason}")
    if lighting.fit is not None:
        print("       re-render vs background: " + ", ".join(
            f"{fit.region} {fit.error:+.1%}" for fit in lighting.fit.regions if fit.error is not None))
    print(f"effects  (planned in {plan.seconds:.1f} s; camera measured on {plan.camera.frames_source})")
    for decision in plan.effects:
        cost = "" if decision.ms_per_sample is None else f"  [{decision.ms_per_sample:.1f} ms/sample]"
        print(f"  {'on ' if decision.on else 'off'}  {decision.name:<16} {decision.reason}{cost}")
        if decision.on and _short(decision.parameters):
            print(f"       {'':<16} {_short(decision.parameters)}")


def _preview(scene: Scene, regions: list[Region], settings: SynthesisSettings, plan: RenderPlan, count: int,
             output: Path) -> int:
    from vc.render.bodies import BodyModel
    from vc.render.preview import contact_sheet
    from vc.render.synthesis import RegionSynthesizer

    bodies = BodyModel()
    synthesizers = [RegionSynthesizer(scene, region, bodies, settings, plan) for region in regions]
    samples = []
    for index in range(count):
        synthesizer = synthesizers[index % len(synthesizers)]
        sample_index = index // len(synthesizers)
        samples.append((f"{synthesizer.region.name} #{sample_index}", synthesizer.sample(sample_index)))
    write_image(output, contact_sheet(samples))
    print(f"preview  {count} samples of {len(regions)} regions -> {output}")
    return 0


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    scene = load_scene(args.scene)
    all_regions = plan_regions(scene)
    regions = _selected_regions(scene, all_regions, args.regions)
    settings = SynthesisSettings(spp=args.spp, seed=args.seed, max_people=args.max_people)
    print(f"scene  {scene.name}  regions {', '.join(region.name for region in regions)}  spp {args.spp}  "
          f"seed {args.seed}")
    # The plan covers every region, whichever are rendered now, so that regions rendered by separate runs into
    # one folder share one light and one camera.
    plan = plan_render(scene, all_regions)
    print_plan(plan)
    if args.preview:
        _writable_folder(args.output.parent)
        return _preview(scene, regions, settings, plan, args.samples or PREVIEW_SAMPLES, args.output)
    if args.samples is None:
        raise InputError(args.output, "--samples", "how many samples per region? (--samples N, N >= 1)")
    _writable_folder(args.output)

    from vc.render.job import RenderRequest, render_dataset

    request = RenderRequest(scene=scene, regions=regions, samples=args.samples, settings=settings,
                            plan=plan, output=args.output, shard_size=args.shard_size)
    summary = render_dataset(request, show_progress=not args.quiet)
    for name, counts in summary["dataset"].items():
        now = summary["rendered_now"].get(name)
        made = f"{now['samples']} rendered now in {now['seconds']:.1f} s" if now else "already complete"
        print(f"  {name:<6} {counts['samples']} samples, {counts['people']} people  ({made})")
    rate = summary["samples_per_second"]
    print(f"done   {summary['seconds']:.1f} s" + (f", {rate:.1f} samples/s" if rate else "")
          + f", {summary['skipped_shards']} finished shards kept  -> {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
