"""The render stage: a scene's regions rendered into a dataset (:mod:`vc.render.dataset`).

Two steps, so that a caller can show the plan (the light and the effects, which take seconds to decide) before
the rendering (which takes minutes): :func:`prepare_render`, then :meth:`RenderJob.run` or
:meth:`RenderJob.preview`.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from vc.errors import InputError
from vc.io import write_image
from vc.render.plan import RenderPlan, plan_render
from vc.scenes.loader import Scene, load_scene
from vc.scenes.regions import Region, plan_regions
from vc.stages.config import RenderSettings
from vc.stages.executors import Executor, InProcess, ShardTask, render_shard


@dataclass
class RenderJob:
    scene: Scene
    regions: list[Region]  # the regions to render now
    settings: RenderSettings
    plan: RenderPlan  # of every region of the scene, whichever are rendered now

    def run(self, output: Path, show_progress: bool = True, executor: Executor | None = None) -> dict:
        """Render the missing shards into ``output`` (finished ones are kept); returns the render summary.
        ``executor``: where the shards are rendered (this process, sample by sample, by default)."""
        from vc.render.job import RenderRequest, render_dataset

        writable_folder(output)
        request = RenderRequest(scene=self.scene, regions=self.regions, samples=self.settings.samples,
                                settings=self.settings.synthesis(), plan=self.plan, output=output,
                                shard_size=self.settings.shard_size)
        if executor is None or isinstance(executor, InProcess):
            return render_dataset(request, show_progress=show_progress)
        return _render_shards_on(executor, request, show_progress)

    def preview(self, output: Path, count: int) -> None:
        """A contact sheet of the first ``count`` samples (the ones the dataset would hold), regions in turn."""
        from vc.render.bodies import BodyModel
        from vc.render.preview import contact_sheet
        from vc.render.synthesis import RegionSynthesizer

        writable_folder(output.parent)
        bodies = BodyModel()
        synthesizers = [RegionSynthesizer(self.scene, region, bodies, self.settings.synthesis(), self.plan)
                        for region in self.regions]
        samples = []
        for index in range(count):
            synthesizer = synthesizers[index % len(synthesizers)]
            sample_index = index // len(synthesizers)
            samples.append((f"{synthesizer.region.name} #{sample_index}", synthesizer.sample(sample_index)))
        write_image(output, contact_sheet(samples))


def _render_shards_on(executor: Executor, request, show_progress: bool) -> dict:
    """Every missing shard as one task of ``executor``; the dataset is the one :func:`render_dataset` writes."""
    from vc.render.job import finish_dataset, start_dataset, summarise

    existing, shards, missing = start_dataset(request)
    tasks = [ShardTask(request, name, shard) for name, planned in missing.items() for shard in planned]
    rendered: dict[str, dict] = {}
    worker_seconds, start = 0.0, time.perf_counter()
    with tqdm(total=sum(task.shard.stop - task.shard.start for task in tasks), unit="sample",
              disable=not show_progress, dynamic_ncols=True, desc=f"shards on {executor.name}") as progress:
        for index, result in executor.map_unordered(render_shard, tasks):
            entry = rendered.setdefault(tasks[index].region, {"samples": 0, "people": 0, "seconds": 0.0})
            entry["samples"] += result["samples"]
            entry["people"] += result["people"]
            entry["seconds"] = round(entry["seconds"] + result["seconds"], 2)  # worker seconds, summed
            worker_seconds += result["seconds"]
            progress.update(result["samples"])
    counts = finish_dataset(request, existing, shards)
    skipped = sum(len(shards[name]) - len(missing[name]) for name in shards)
    return {**summarise(request, counts, rendered, skipped, time.perf_counter() - start,
                        {"shard_total": worker_seconds}), "executor": executor.name}


def prepare_render(scene_path: Path, settings: RenderSettings, region_names: list[str] | None = None) -> RenderJob:
    """Load the scene, plan its regions and decide the light and the effects for all of them (so that regions
    rendered by separate runs into one folder share one light and one camera)."""
    scene = load_scene(scene_path)
    regions = plan_regions(scene)
    return RenderJob(scene, selected_regions(scene, regions, region_names), settings, plan_render(scene, regions))


def render(scene_path: Path, output: Path, settings: RenderSettings, region_names: list[str] | None = None,
           show_progress: bool = True) -> dict:
    """The whole stage: :func:`prepare_render` then :meth:`RenderJob.run`."""
    return prepare_render(scene_path, settings, region_names).run(output, show_progress)


def selected_regions(scene: Scene, regions: list[Region], names: list[str] | None) -> list[Region]:
    if not names:
        return regions
    known = {region.name: region for region in regions}
    unknown = [name for name in names if name not in known]
    if unknown:
        raise InputError(scene.path, "--regions", f"unknown region {', '.join(unknown)} (the scene plans "
                                                  f"{', '.join(known)})")
    return [known[name] for name in dict.fromkeys(names)]


def writable_folder(path: Path) -> None:
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(path, "-o", f"cannot create the output folder ({error.strerror})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(path, "-o", "the output folder is not writable")


def describe_plan(plan: RenderPlan) -> list[str]:
    """The light and the effects plan as lines: each effect on/off, why, its parameters and its cost per sample."""
    lighting = plan.lighting
    lines = [f"response  {plan.response.name} ({plan.response.reason})", f"light  {lighting.summary()}"]
    if lighting.estimate is not None:
        lines.append(f"       {lighting.estimate.reason}")
    if lighting.fit is not None:
        lines.append("       re-render vs background: " + ", ".join(
            f"{fit.region} {fit.error:+.1%}" for fit in lighting.fit.regions if fit.error is not None))
    lines.append(f"effects  (planned in {plan.seconds:.1f} s; camera measured on {plan.camera.frames_source})")
    for decision in plan.effects:
        cost = "" if decision.ms_per_sample is None else f"  [{decision.ms_per_sample:.1f} ms/sample]"
        lines.append(f"  {'on ' if decision.on else 'off'}  {decision.name:<16} {decision.reason}{cost}")
        if decision.on and _short(decision.parameters):
            lines.append(f"       {'':<16} {_short(decision.parameters)}")
    return lines


def _short(parameters: dict) -> str:
    """An effect's parameters on one line (nested per-region values left to the manifest)."""
    return ", ".join(f"{key} {value}" for key, value in parameters.items() if not isinstance(value, dict | list))
