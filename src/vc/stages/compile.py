"""A whole compile: check -> render -> train -> export -> self-test, resumable.

``OUT/compile_config.yaml`` holds the full config (:class:`vc.stages.config.CompileConfig`), ``OUT/compile.json``
each finished stage's record. Compiling again with the same scene and config skips the finished stages and
resumes the interrupted one where it stopped (render shards and training checkpoints are kept); another scene or
config runs every stage again, reusing kept work where it still fits.

What a caller shows while it runs goes through a :class:`Reporter` (the command prints; a benchmark may stay
silent).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

from vc.errors import InputError
from vc.evaluation.selftest import self_test_bundle
from vc.io import write_json
from vc.model.trainer import RegionResult
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions
from vc.stages.config import CONFIG_FILE, CompileConfig, write_config
from vc.stages.executors import Executor, InProcess, LocalProcesses
from vc.stages.export import ExportResult, export
from vc.stages.render import RenderJob, prepare_render
from vc.stages.train import TrainingJob, prepare_training

STATE = "compile.json"
STAGES = ("check", "render", "train", "export", "self-test")
#: Scenes compiled at once on a cluster by default: each plans its light on the caller (seconds of CPU), then keeps
#: its shards (tens) and its regions' training (a few tasks) in flight. A cluster of C CPUs stays busy through
#: training with about C / 3 scenes in flight.
SCENES_IN_FLIGHT = 16


class Reporter:
    """What a compile tells its caller; each hook does nothing here, a command overrides what it shows."""

    def stage_started(self, name: str) -> None: ...

    def stage_skipped(self, name: str, record: dict) -> None: ...

    def settings_changed(self, state_path: Path) -> None: ...

    def rendering(self, job: RenderJob) -> None: ...

    def rendered(self, summary: dict, output: Path) -> None: ...

    def training(self, job: TrainingJob) -> None: ...

    def trained(self, results: list[RegionResult], run: Path) -> None: ...

    def exported(self, result: ExportResult, bundle: Path) -> None: ...


class Compilation:
    """The stages of one compile of ``scene_path`` into ``output`` and their record."""

    def __init__(self, scene_path: Path, output: Path, config: CompileConfig, show_progress: bool = True,
                 reporter: Reporter | None = None, executor: Executor | None = None) -> None:
        self.scene_path, self.output, self.config = Path(scene_path), Path(output), config
        self.show_progress, self.reporter, self.executor = show_progress, reporter or Reporter(), executor
        self.scene = load_scene(scene_path)
        self.settings = {"scene": str(scene_path), "scene_hash": self.scene.content_hash, **config.to_dict()}
        self.renders, self.run_folder = self.output / "renders", self.output / "run"
        self.bundle, self.overlay = self.output / "bundle", self.output / "overlay.png"
        self.test_frame = self.output / "test_frame.png"
        self.state = self._read_state()

    def run(self) -> dict:
        """Every stage not finished before, in order; returns the record (``compile.json``'s content)."""
        write_config(self.config, self.output / CONFIG_FILE)
        stages: dict[str, Callable[[], dict]] = {"check": self.check, "render": self.render, "train": self.train,
                                                 "export": self.export, "self-test": self.self_test}
        for name in STAGES:
            self._run_stage(name, stages[name])
        return self.state

    def _read_state(self) -> dict:
        path = self.output / STATE
        if path.is_file():
            try:
                state = json.loads(path.read_text())
            except json.JSONDecodeError as error:
                raise InputError(path, "", f"not valid JSON ({error}); delete it to start over") from None
            if state.get("settings") == self.settings:
                return state
            self.reporter.settings_changed(path)
        return {"settings": self.settings, "stages": {}}

    def _run_stage(self, name: str, stage: Callable[[], dict]) -> dict:
        record = self.state["stages"].get(name)
        if record:
            self.reporter.stage_skipped(name, record)
            return record
        self.reporter.stage_started(name)
        start = time.perf_counter()
        result = stage()
        record = {"seconds": round(time.perf_counter() - start, 1), **result}
        self.state["stages"][name] = record
        write_json(self.output / STATE, self.state)
        return record

    def check(self) -> dict:
        return {"regions": [{"name": r.name, "input_size": list(r.input_size)} for r in plan_regions(self.scene)]}

    def render(self) -> dict:
        job = prepare_render(self.scene_path, self.config.render)
        self.reporter.rendering(job)
        self.reporter.rendered(job.run(self.renders, self.show_progress, self.executor), self.renders)
        return {}

    def train(self) -> dict:
        job = prepare_training(self.renders, self.config.train)
        self.reporter.training(job)
        results = job.run(self.run_folder, self.show_progress, self.executor)
        self.reporter.trained(results, self.run_folder)
        kept = ("ap50", "pckh", "mask_iou", "recall_overlapping")
        return {"held_out": {result.region: {key: result.to_dict()[key] for key in kept} for result in results}}

    def export(self) -> dict:
        result = export(self.run_folder, self.bundle, self.config.export, show_progress=self.show_progress,
                        scene=self.scene)
        self.reporter.exported(result, self.bundle)
        size = sum(path.stat().st_size for path in self.bundle.rglob("*") if path.is_file())
        return {"bundle_bytes": size, "precision": {r["name"]: r["precision"] for r in result.manifest["regions"]}}

    def self_test(self) -> dict:
        return self_test_bundle(self.bundle, self.renders, self.scene.image_path, self.config.self_test,
                                self.overlay, self.test_frame).to_dict()


def compile_scene(scene_path: Path, output: Path, config: CompileConfig, show_progress: bool = True,
                  reporter: Reporter | None = None, executor: Executor | None = None) -> dict:
    """Compile ``scene_path`` into ``output`` (resuming what is there); returns the compile record. ``executor``
    runs the render shards and the regions' training (:mod:`vc.stages.executors`; this process by default)."""
    return Compilation(scene_path, output, config, show_progress, reporter, executor).run()


def scene_outputs(scene_paths: list[Path], root: Path) -> dict[Path, Path]:
    """Each scene's output folder when many compile at once: ``root/<scene name>`` (names must differ)."""
    outputs: dict[Path, Path] = {}
    for path in scene_paths:
        folder = root / load_scene(path).name
        clash = next((other for other, taken in outputs.items() if taken == folder), None)
        if clash is not None:
            raise InputError(path, "name", f"is also the name of {clash}: scenes compiled together need their own "
                                           "names (each compiles into OUT/<name>)")
        outputs[Path(path)] = folder
    return outputs


def compile_scenes(scene_paths: list[Path], root: Path, config: CompileConfig, executor: Executor,
                   on_done: Callable[[Path, dict], None] | None = None, in_flight: int = SCENES_IN_FLIGHT
                   ) -> dict[Path, dict]:
    """Compile many scenes into ``root/<scene name>``. On a cluster each scene's stages run in a thread of their
    own (``in_flight`` at a time), so that the shards and regions of those scenes are in flight together; in this
    process, or in this machine's worker processes (one pool of them), they compile in turn. Returns each scene's
    compile record; ``on_done`` hears of each as it finishes."""
    from concurrent.futures import ThreadPoolExecutor, as_completed

    outputs = scene_outputs(scene_paths, root)
    records: dict[Path, dict] = {}
    at_once = 1 if isinstance(executor, InProcess | LocalProcesses) else min(len(outputs), in_flight)
    with ThreadPoolExecutor(max_workers=at_once) as threads:
        futures = {threads.submit(compile_scene, path, output, config, False, None, executor): path
                   for path, output in outputs.items()}
        for future in as_completed(futures):
            records[futures[future]] = future.result()
            if on_done is not None:
                on_done(futures[future], records[futures[future]])
    return records
