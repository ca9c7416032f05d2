"""Render throughput: labelled samples per second per region and spp, and where the time goes.

    python -m benchmarks.render_throughput [--scene examples/scenes/pets09_s2l1/scene.yaml] [--spp 4 16 64]
                                           [--samples 40] [--warmup 5] [--out benchmarks/results/render_throughput]
    python -m benchmarks.render_throughput --photometry [--scene ...] [--samples 40] [--out DIR]
    python -m benchmarks.render_throughput --sun-course [--scene examples/scenes/demo_dated/scene.yaml] [--samples 40]
    python -m benchmarks.render_throughput --processes 12 [--scene ...] [--samples 400] [--out DIR]

Each sample is what ``vc-render`` writes: people sampled and posed, rendered, composited, labelled, and the
image and mask PNGs and the shard's annotations written by the dataset writer (to a temporary folder). One
process, all cores (2 on the reference machine). Writes ``render_throughput.json``, ``render_throughput.md`` (table) and
``render_throughput.png`` (samples/s per region and spp; time per step at the reference spp) to ``--out``.

``--photometry`` times each region at the reference spp twice in one run, in turn: with photometric matching off
(the default sun of an explicit ``lighting:`` block, no camera effects) and matched (the scene's own plan). The
throughput may fall by no more than what the matched plan's effects cost: the run writes both rates, the measured
difference per sample, and the effects' own time per sample (the samples' ``effect.*`` timings and the plan's
estimate) to ``render_throughput_photometry.json`` and ``.md``, with the machine's CPU model, since rates from
different machines do not compare.

``--sun-course`` times each region of a scene that says where and when its background was taken (default: the
dated demo, ``examples/scenes/demo_dated/scene.yaml``) at the reference spp twice in one run, in turn: under the
photographed sun alone and over the sun's course (:mod:`vc.render.sun_course`). It writes what building each position
costs once per region (the background relit and a renderer of its own), the samples/s of both once every position is
built, and their ratio, to ``render_throughput_sun_course.json`` and ``.md``.

``--processes N [N ...]`` times the whole render stage instead (every region, ``--samples`` each at 16 spp, shards
of :data:`PROCESS_SHARD` samples), wall clock, in this process and then with ``vc-compile --executor processes``'s
``N`` worker processes, in turn in one run: what several renderers at once deliver on this machine, as a ratio to
one. Worker start-up (imports, the body model, each region's scene) counts, as it does in a compile. Writes
``render_throughput_processes.json`` and ``.md``.
"""

from __future__ import annotations

import argparse
import json
import shutil
import tempfile
import time
from collections import defaultdict
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from benchmarks import EXAMPLE_SCENES, display_path, results_folder  # noqa: E402
from vc.cores import cpu_facts  # noqa: E402
from vc.io import write_json  # noqa: E402
from vc.render import dataset  # noqa: E402
from vc.render.bodies import BodyModel  # noqa: E402
from vc.render.plan import RenderPlan, plan_render  # noqa: E402
from vc.render.synthesis import RegionSynthesizer, SynthesisSettings  # noqa: E402
from vc.scenes.loader import Scene, load_scene  # noqa: E402
from vc.scenes.regions import plan_regions  # noqa: E402
from vc.scenes.schema import Lighting  # noqa: E402

REFERENCE_SPP = 16


def measure(synthesizer: RegionSynthesizer, samples: int, warmup: int, scratch: Path) -> dict:
    """Samples/s as ``vc-render`` gets them: the dataset writer writes the shard (PNGs and annotations)."""
    for index in range(warmup):
        synthesizer.sample(10_000_000 + index)
    steps: dict[str, float] = defaultdict(float)
    people = 0

    def timed_samples():
        nonlocal people
        for index in range(samples):
            sample = synthesizer.sample(index)
            for step, seconds in sample.timings.items():
                steps[step] += seconds
            people += len(sample.annotations)
            yield sample

    shard = dataset.Shard(synthesizer.region.name, 0, 0, samples)
    shutil.rmtree(shard.folder(scratch), ignore_errors=True)
    start = time.perf_counter()
    dataset.write_shard(scratch, shard, timed_samples(), {})
    elapsed = time.perf_counter() - start
    timed = ("pose", "dress", "render", "composite", "labels")
    steps["writing (not overlapped)"] = elapsed - sum(steps[step] for step in timed)
    heights = []
    for index in range(min(samples, 10)):
        heights += [a["bbox"][3] for a in synthesizer.sample(index).annotations]
    return {
        "samples_per_second": round(samples / elapsed, 2),
        "ms_per_sample": round(1000 * elapsed / samples, 1),
        "people_per_sample": round(people / samples, 2),
        "median_visible_height_px": round(float(np.median(heights)), 1) if heights else None,
        "ms_per_step": {step: round(1000 * seconds / samples, 2) for step, seconds in sorted(steps.items())},
    }


def photometry_off(scene: Scene) -> Scene:
    """``scene`` rendered as before photometric matching: the default sun and sky, geometric effects only."""
    geometric = ["lens_distortion", "shadows"] if not scene.camera.distortion.is_identity else ["shadows"]
    return replace(scene, lighting=Lighting(), effects=geometric, video_path=None)


def compare_photometry(scene: Scene, bodies: BodyModel, samples: int, warmup: int, scratch: Path) -> list[dict]:
    """Per region, samples/s with photometric matching off and matched, measured in turn in this process."""
    regions = plan_regions(scene)
    plans = {"off": plan_render(photometry_off(scene), regions), "matched": plan_render(scene, regions)}
    rows = []
    for region in regions:
        row = {"region": region.name, "input_size": list(region.input_size)}
        for name, plan in plans.items():
            rendered = photometry_off(scene) if name == "off" else scene
            synthesizer = RegionSynthesizer(rendered, region, bodies, SynthesisSettings(spp=REFERENCE_SPP), plan)
            row[name] = measure(synthesizer, samples, warmup, scratch)
        effects = {step: ms for step, ms in row["matched"]["ms_per_step"].items() if step.startswith("effect.")}
        row["slowdown_ms_per_sample"] = round(row["matched"]["ms_per_sample"] - row["off"]["ms_per_sample"], 1)
        row["effects_ms_per_sample"] = round(sum(effects.values()), 1)
        row["planned_effects_ms_per_sample"] = round(sum(d.ms_per_sample or 0.0 for d in plans["matched"].effects), 1)
        print(json.dumps(row))
        rows.append(row)
    return rows


def without_sun_course(plan: RenderPlan) -> RenderPlan:
    """``plan`` with its samples under the photographed sun alone."""
    return replace(plan, effects=[replace(decision, on=False, reason="switched off for the comparison")
                                  if decision.name == "sun_course" else decision for decision in plan.effects])


def compare_sun_course(scene: Scene, bodies: BodyModel, samples: int, warmup: int, scratch: Path) -> dict:
    """Per region: the seconds each position of the sun's course takes to build, and samples/s under the photographed
    sun alone and over the course (every position built first), measured in turn in this process."""
    regions = plan_regions(scene)
    plan = plan_render(scene, regions)
    if not plan.sun_course:
        reason = next(decision.reason for decision in plan.effects if decision.name == "sun_course")
        raise SystemExit(f"{display_path(scene.path)}: no sun course to measure: {reason}")
    rows = []
    for region in regions:
        settings = SynthesisSettings(spp=REFERENCE_SPP)
        photographed = RegionSynthesizer(scene, region, bodies, settings, without_sun_course(plan))
        course = RegionSynthesizer(scene, region, bodies, settings, plan)
        build = []
        for index in range(1, len(plan.sun_course)):
            start = time.perf_counter()
            course.light(index)
            build.append(time.perf_counter() - start)
        row = {"region": region.name, "input_size": list(region.input_size), "positions": len(plan.sun_course),
               "build_seconds_per_position": round(float(np.mean(build)), 2),
               "build_seconds": round(float(np.sum(build)), 1),
               "photographed": measure(photographed, samples, warmup, scratch),
               "course": measure(course, samples, warmup, scratch)}
        row["ratio"] = round(row["course"]["ms_per_sample"] / row["photographed"]["ms_per_sample"], 2)
        print(json.dumps(row), flush=True)
        rows.append(row)
    return {"scene": display_path(scene.path), "cpu": cpu_facts()[0], "spp": REFERENCE_SPP, "samples": samples,
            "positions": [position.to_dict() for position in plan.sun_course], "rows": rows}


def write_sun_course(report: dict, out: Path) -> None:
    """``render_throughput_sun_course.json`` and ``.md`` from :func:`compare_sun_course`'s ``report``."""
    write_json(out / "render_throughput_sun_course.json", report)
    hours = ", ".join(position["time"][11:16] for position in report["positions"][1:])
    lines = [f"The sun's course on {report['scene']}: the photographed sun and {len(report['positions']) - 1} more "
             f"({hours}), {report['spp']} spp, {report['samples']} samples per region and arm, one run on "
             f"{report['cpu']} (`python -m benchmarks.render_throughput --sun-course`).", "",
             "| region | input | build s per position | build s | photographed sun samples/s | course samples/s | "
             "course / photographed, time per sample |", "|---|---|---|---|---|---|---|"]
    lines += [f"| {r['region']} | {r['input_size'][0]}x{r['input_size'][1]} | {r['build_seconds_per_position']} | "
              f"{r['build_seconds']} | {r['photographed']['samples_per_second']} | "
              f"{r['course']['samples_per_second']} | {r['ratio']}x |" for r in report["rows"]]
    (out / "render_throughput_sun_course.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


#: Samples per shard in ``--processes`` runs: small enough that every worker gets several.
PROCESS_SHARD = 20


def compare_processes(scene_path: Path, counts: list[int], samples: int, scratch: Path) -> list[dict]:
    """The render stage in this process, then in each count of worker processes: wall seconds and samples/s."""
    from vc.stages.config import RenderSettings
    from vc.stages.executors import InProcess, LocalProcesses
    from vc.stages.render import prepare_render

    job = prepare_render(scene_path, RenderSettings(samples=samples, shard_size=PROCESS_SHARD))
    total = samples * len(job.regions)
    rows = []
    for executor in [InProcess(), *(LocalProcesses(count) for count in counts)]:
        output = scratch / executor.name / str(getattr(executor, "processes", 1))
        start = time.perf_counter()
        job.run(output, show_progress=False, executor=executor)
        seconds = time.perf_counter() - start
        rows.append({"executor": executor.name, "processes": getattr(executor, "processes", 1),
                     "samples": total, "seconds": round(seconds, 1), "samples_per_second": round(total / seconds, 2)})
        rows[-1]["ratio_to_one_process"] = round(rows[-1]["samples_per_second"] / rows[0]["samples_per_second"], 2)
        print(json.dumps(rows[-1]), flush=True)
    return rows


def processes_report(rows: list[dict], scene_path: Path) -> dict:
    """The ``--processes`` rows with what they were measured on: the scene, the CPU and Mitsuba's variant."""
    from vc.render.mitsuba_setup import mitsuba

    return {"scene": display_path(scene_path), "machine": cpu_facts()[0], "mitsuba_variant": mitsuba().variant(),
            "shard_size": PROCESS_SHARD, "rows": rows}


def write_processes(report: dict, out: Path) -> None:
    """``render_throughput_processes.json`` and ``.md`` from :func:`processes_report`'s ``report``."""
    write_json(out / "render_throughput_processes.json", report)
    rows = report["rows"]
    lines = [f"Render stage of {report['scene']}, 16 spp, {rows[0]['samples']} samples over its regions, on "
             f"{report['machine']} with Mitsuba `{report['mitsuba_variant']}` "
             "(`python -m benchmarks.render_throughput --processes ...`).", "",
             "| renderers | seconds | samples/s | against one process |", "|---|---|---|---|"]
    lines += [f"| {r['processes']} ({r['executor']}) | {r['seconds']} | {r['samples_per_second']} | "
              f"{r['ratio_to_one_process']}x |" for r in rows]
    (out / "render_throughput_processes.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def _write_photometry(rows: list[dict], out: Path) -> None:
    machine = cpu_facts()[0]
    write_json(out / "render_throughput_photometry.json", {"cpu": machine, "spp": REFERENCE_SPP, "rows": rows})
    lines = [f"Render throughput with photometric matching off and matched, {REFERENCE_SPP} spp, one run on "
             f"{machine}",
             "", "| region | input | off samples/s | matched samples/s | slower by ms/sample | effects ms/sample |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['region']} | {r['input_size'][0]}x{r['input_size'][1]} | "
                     f"{r['off']['samples_per_second']} | {r['matched']['samples_per_second']} | "
                     f"{r['slowdown_ms_per_sample']} | {r['effects_ms_per_sample']} |")
    (out / "render_throughput_photometry.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def _plot(results: list[dict], path: Path) -> None:
    figure, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5))
    for region in dict.fromkeys(r["region"] for r in results):
        rows = [r for r in results if r["region"] == region]
        left.plot([r["spp"] for r in rows], [r["samples_per_second"] for r in rows], "o-",
                  label=f"{region} {rows[0]['input_size'][0]}x{rows[0]['input_size'][1]}")
    left.axhline(15, color="grey", linestyle="--", linewidth=1, label="target 15/s")
    left.set(xscale="log", xlabel="samples per pixel", ylabel="labelled samples / s", title="Render throughput")
    left.legend()
    reference = [r for r in results if r["spp"] == REFERENCE_SPP] or results
    steps = ["pose", "dress", "render.update_scene", "render.windows", "render.trace", "render.layers",
             "render.distortion_warp", "composite", "labels", "writing (not overlapped)"]
    bottom = np.zeros(len(reference))
    for step in steps:
        values = np.array([r["ms_per_step"].get(step, 0.0) for r in reference])
        right.bar([r["region"] for r in reference], values, bottom=bottom, label=step)
        bottom += values
    right.set(ylabel="ms per sample", title=f"Where the time goes ({reference[0]['spp']} spp)")
    right.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", type=Path)
    parser.add_argument("--spp", type=int, nargs="+", default=[4, 16, 64])
    parser.add_argument("--samples", type=int, default=40)
    parser.add_argument("--warmup", type=int, default=5)
    parser.add_argument("--out", type=Path, default=results_folder("render_throughput"))
    parser.add_argument("--photometry", action="store_true",
                        help="compare photometric matching off and matched at the reference spp instead")
    parser.add_argument("--sun-course", action="store_true",
                        help="compare the photographed sun alone and the sun's course at the reference spp instead "
                             "(default scene: the dated demo)")
    parser.add_argument("--processes", type=int, nargs="+", metavar="N",
                        help="time the render stage in this process and in N worker processes instead")
    args = parser.parse_args()

    default = "demo_dated/scene.yaml" if args.sun_course else "pets09_s2l1/scene.yaml"
    args.scene = args.scene or EXAMPLE_SCENES / default
    if args.processes:
        args.out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(prefix="vc-render-processes-") as scratch:
            rows = compare_processes(args.scene, args.processes, args.samples, Path(scratch))
        write_processes(processes_report(rows, args.scene), args.out)
        return
    scene = load_scene(args.scene)
    start = time.perf_counter()
    bodies = BodyModel()
    print(f"body model built in {time.perf_counter() - start:.1f} s")
    scratch = tempfile.mkdtemp(prefix="vc-render-bench-")
    args.out.mkdir(parents=True, exist_ok=True)
    if args.sun_course:
        report = compare_sun_course(scene, bodies, args.samples, args.warmup, Path(scratch))
        shutil.rmtree(scratch)
        write_sun_course(report, args.out)
        return
    if args.photometry:
        rows = compare_photometry(scene, bodies, args.samples, args.warmup, Path(scratch))
        shutil.rmtree(scratch)
        _write_photometry(rows, args.out)
        return
    plan = plan_render(scene, plan_regions(scene))
    results = []
    for region in plan_regions(scene):
        for spp in args.spp:
            settings = SynthesisSettings(spp=spp)
            synthesizer = RegionSynthesizer(scene, region, bodies, settings, plan)
            row = {"scene": scene.name, "region": region.name, "input_size": list(region.input_size), "spp": spp,
                   **measure(synthesizer, args.samples, args.warmup, Path(scratch))}
            print(json.dumps(row))
            results.append(row)

    shutil.rmtree(scratch)
    write_json(args.out / "render_throughput.json", {"effects": [e.to_dict() for e in plan.effects],
                                                     "lighting": plan.lighting.to_dict(), "results": results})
    lines = ["| region | input | spp | samples/s | ms/sample | people/sample | median person px | "
             "pose | trace | other render | composite | labels | writing |", "|" + "---|" * 13]
    for r in results:
        ms = r["ms_per_step"]
        other = sum(v for k, v in ms.items() if k.startswith("render.") and k != "render.trace")
        lines.append(f"| {r['region']} | {r['input_size'][0]}x{r['input_size'][1]} | {r['spp']} | "
                     f"{r['samples_per_second']} | {r['ms_per_sample']} | {r['people_per_sample']} | "
                     f"{r['median_visible_height_px']} | {ms.get('pose', 0):.1f} | "
                     f"{ms.get('render.trace', 0):.1f} | {other:.1f} | {ms.get('composite', 0):.1f} | "
                     f"{ms.get('labels', 0):.1f} | {ms.get('writing (not overlapped)', 0):.1f} |")
    (args.out / "render_throughput.md").write_text("\n".join(lines) + "\n")
    _plot(results, args.out / "render_throughput.png")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
