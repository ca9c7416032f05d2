"""Render a scene's dataset: plan shards, skip finished ones, render the rest with a progress bar, summarise.

Resumable by construction: finished shards are never touched (one that no longer matches its checksums is
re-made), a partial one is redone, and every sample is a
pure function of the manifest's settings — so a run killed at any moment and started again with the same
command yields the same bytes as an uninterrupted run.
"""

from __future__ import annotations

import logging
import shutil
import time
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from pathlib import Path

from tqdm import tqdm

from vc.io import write_json
from vc.render import dataset
from vc.render.bodies import BodyModel
from vc.render.plan import RenderPlan
from vc.render.synthesis import RegionSynthesizer, RenderedSample, SynthesisSettings
from vc.scenes.loader import Scene
from vc.scenes.regions import Region
from vc.versions import package_versions

DEFAULT_SHARD_SIZE = 100
#: Shards by region name.
Shards = dict[str, list[dataset.Shard]]
logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class RenderRequest:
    scene: Scene
    regions: list[Region]
    samples: int  # per region
    settings: SynthesisSettings
    plan: RenderPlan
    output: Path
    shard_size: int = DEFAULT_SHARD_SIZE


def _samples(synthesizer: RegionSynthesizer, shard: dataset.Shard, timings: dict[str, float], progress: tqdm
             ) -> Iterator[RenderedSample]:
    for index in range(shard.start, shard.stop):
        sample = synthesizer.sample(index)
        for stage, seconds in sample.timings.items():
            timings[stage] += seconds
        progress.update(1)
        yield sample


def _intact(root: Path, shard: dataset.Shard) -> bool:
    """Whether a shard is finished and matches its checksums. A damaged one is removed (with a line saying which
    file was wrong) so that it is rendered again: its samples are a pure function of the settings, so the new
    shard has the bytes the old one had."""
    if not dataset.is_complete(root, shard):
        return False
    damaged = dataset.damaged_files(shard.folder(root))
    if damaged:
        logger.warning("%s: %s does not match its checksum; rendering the shard again",
                       shard.folder(root), damaged[0])
        shutil.rmtree(shard.folder(root))
    return not damaged


def manifest(request: RenderRequest, counts: dict[str, dict] | None = None) -> dict:
    """The dataset manifest: what the shards were rendered from and with, and (when known) what they hold."""
    scene_camera = request.scene.camera
    regions = {}
    for region in request.regions:
        entry = {**region.to_dict(), "samples": request.samples,
                 "shards": len(dataset.plan_shards(region.name, request.samples, request.shard_size)),
                 "camera": region.camera(scene_camera).to_dict()}
        if counts is not None:
            entry["counts"] = counts[region.name]
        regions[region.name] = entry
    return {
        "format_version": dataset.FORMAT_VERSION,
        "scene": request.scene.name,
        "scene_hash": request.scene.content_hash,
        "camera": scene_camera.to_dict(),  # the full frame's camera, which regions crop (an exported bundle's)
        "settings": {**asdict(request.settings), "shard_size": request.shard_size},
        **dataset.plan_entries(request.plan.to_dict()),
        "categories": [dataset.PERSON_CATEGORY],
        "regions": regions,
        "versions": package_versions(),
    }


def shard_info(request: RenderRequest, region: Region) -> dict:
    """What every shard of ``region`` records about where it came from (its ``annotations.json`` info)."""
    return {"description": f"vc-render samples of scene {request.scene.name}, region {region.name}",
            "scene": request.scene.name, "scene_hash": request.scene.content_hash, "region": region.name,
            "format_version": dataset.FORMAT_VERSION}


def start_dataset(request: RenderRequest) -> tuple[dict, Shards, Shards]:
    """Check and write the manifest; returns the manifest found before, every planned shard and the missing ones
    (a damaged shard is removed and counted missing), by region."""
    root = request.output
    existing = dataset.read_manifest(root, missing_ok=True)
    dataset.check_manifest(root, existing, manifest(request))
    dataset.write_manifest(root, manifest(request), existing)
    shards = {region.name: dataset.plan_shards(region.name, request.samples, request.shard_size)
              for region in request.regions}
    missing = {name: [shard for shard in planned if not _intact(root, shard)] for name, planned in shards.items()}
    return existing, shards, missing


def finish_dataset(request: RenderRequest, existing: dict, shards: Shards) -> dict:
    """Count what every region's shards hold into the manifest; returns the counts by region."""
    counts = {name: {"samples": 0, "people": 0} for name in shards}
    for name, planned in shards.items():
        for shard in planned:
            shard_counts = dataset.shard_counts(request.output, shard)
            counts[name]["samples"] += shard_counts["samples"]
            counts[name]["people"] += shard_counts["people"]
    dataset.write_manifest(request.output, manifest(request, counts), existing)
    return counts


def summarise(request: RenderRequest, counts: dict, rendered: dict, skipped: int, seconds: float,
              timings: dict[str, float]) -> dict:
    """The run summary (also written as ``render_summary.json``)."""
    sample_count = sum(entry["samples"] for entry in rendered.values())
    stage_seconds = {stage: round(value, 3) for stage, value in timings.items()}
    if sample_count and "shard_total" in timings:
        per_sample = {"pose", "dress", "render", "composite", "labels"}
        stage_seconds["write_and_other"] = round(timings["shard_total"] - sum(
            timings.get(stage, 0.0) for stage in per_sample), 3)
    summary = {
        "scene": request.scene.name,
        "output": str(request.output),
        "rendered_now": rendered,
        "skipped_shards": skipped,
        "dataset": counts,
        "seconds": round(seconds, 2),
        # what the run delivered, wall clock; and one renderer's own rate (equal in this process, lower per worker
        # where several share a machine)
        "samples_per_second": round(sample_count / seconds, 2) if sample_count and seconds > 0 else None,
        "samples_per_renderer_second": round(sample_count / timings["shard_total"], 2) if sample_count else None,
        "stage_seconds": stage_seconds,
        "plan_seconds": round(request.plan.seconds, 2),
        "lighting": request.plan.lighting.to_dict(),
        "effects": [decision.to_dict() for decision in request.plan.effects],
    }
    write_json(request.output / "render_summary.json", summary)
    return summary


def render_dataset(request: RenderRequest, bodies: BodyModel | None = None, show_progress: bool = True) -> dict:
    """Render every missing shard of ``request`` in this process; returns the run summary."""
    root = request.output
    existing, shards, missing = start_dataset(request)
    to_render = sum(shard.stop - shard.start for planned in missing.values() for shard in planned)

    start = time.perf_counter()
    timings: dict[str, float] = defaultdict(float)
    rendered: dict[str, dict] = {}
    if to_render:
        bodies = bodies or BodyModel()
        timings["body_model"] = time.perf_counter() - start
    with tqdm(total=to_render, unit="sample", disable=not show_progress, dynamic_ncols=True) as progress:
        for region in request.regions:
            if not missing[region.name]:
                continue
            region_start = time.perf_counter()
            synthesizer = RegionSynthesizer(request.scene, region, bodies, request.settings, request.plan)
            timings["scene_setup"] += time.perf_counter() - region_start
            samples = people = 0
            for shard in missing[region.name]:
                progress.set_description(f"{region.name} {shard.name}")

                mark = time.perf_counter()
                counts = dataset.write_shard(root, shard, _samples(synthesizer, shard, timings, progress),
                                             shard_info(request, region))
                timings["shard_total"] += time.perf_counter() - mark
                samples += counts["samples"]
                people += counts["people"]
                progress.set_postfix(people=people)
            rendered[region.name] = {"samples": samples, "people": people,
                                     "seconds": round(time.perf_counter() - region_start, 2)}
    elapsed = time.perf_counter() - start
    counts = finish_dataset(request, existing, shards)
    skipped = sum(len(shards[name]) - len(missing[name]) for name in shards)
    return summarise(request, counts, rendered, skipped, elapsed, timings)
