"""What each compile knob buys: accuracy against compile time and runtime, one knob at a time.

    python -m benchmarks.accuracy_vs_time --scene SCENE --knob spp [samples ...] [--work DIR]
        [--knob width --value 16]   # one knob's chosen values; its others keep their earlier results
        [--dev-video V --dev-gt GT.txt --dev-frames 1:400:5] [--out benchmarks/results/accuracy_vs_time]
        [--no-runtime]

Every point is the standard compile (2 000 samples/region at 16 spp with effects, people placed alone, the ``fast``
network, 1 800 steps, per-region models, fp32) with one knob changed (:data:`KNOBS`):

- ``spp`` 4 / 16 / 64, ``effects`` on / off (shadows; lens distortion stays: labels must follow the lens),
  ``samples`` per region 1k / 2k / 5k / 20k / 50k,
- ``arch`` fast / fast-dw / dense9, ``width`` 16 / 32 / 64, ``sb_units`` 1 / 2 / 3,
- ``input`` (the planner's target person height; the scene's own is the standard point) 40 / 48 / 64 / 80 px,
  ``regions`` per-region / single (SPN-G),
- ``precision`` fp32 / fp16 / int8,
- ``seed`` 0 / 1 / 2: the training seed (weights and data order), which trades nothing: the spread between seeds is
  the noise floor that the other knobs' differences must clear;
- ``photometry`` (:data:`PHOTOMETRY`): the renders' light and camera — off (the default sun of an explicit
  ``lighting:`` block, no camera effects: every point measured before photometric matching), the light estimated
  from the background alone, or matched (light and every camera effect the scene calls for: the standard compile),
  and matched less one camera effect at a time (``python -m benchmarks.effects_ablation`` runs this knob and adds each
  variant's render cost per sample);
- ``groups``: people placed alone (every point's reference, whatever the scene's own ``priors.group_rate``) or
  with a group rate of 0.3 (a person starts a group of 2-4 walking abreast or in file; ``render/placement.py``),
  each with training seeds 0, 1 and 2 (renders shared);
- ``clothing``: what the people wear (``priors.clothing``): the scene's own mixed street clothing against winter
  coats, each with training seeds 0, 1 and 2 (renders shared) and the compute knob's faster trainer;
- ``separable``: the ``fast`` network (off) against ``fast-sep`` (on, the default since), whose SB units factor
  each 13x13 into a 13x1 then a 1x13 (same receptive field, a third less int8 network time), seeds 0, 1 and 2,
  faster trainer;
- ``groups_sep``: the ``groups`` knob again on ``fast-sep`` with the faster trainer: people alone (the
  ``separable`` knob's "on" runs) against a group rate of 0.3, seeds 0, 1 and 2 (renders shared);
- ``stem``: ``fast-sep``'s stem (a 5x5 at half resolution, then a strided 3x3) against one 4x4 convolution over
  non-overlapping patches (``fast-patch``), both with the groups of ``groups_sep``, seeds 0, 1 and 2;
- ``compute``: the trainer in fp32 (the standard compile) or in bfloat16 autocast with channels-last activations
  (``TRAINING_COMPUTE``; about twice the images per second where the CPU has bf16 instructions), with training
  seeds 0, 1 and 2: whether the faster compile holds accuracy.

Measured per point: held-out synthetic AP50 and PCKh@0.5 (mean over regions, on the point's own renders: across the
knobs that change the renders, such as effects or regions, the held-out sets differ and real AP50 is the comparable
number); real AP50 on the development frames through ``vc-eval`` when ``--dev-video`` is given (each frame on its own,
as before tracking, with the tracked AP50 beside it, on all of them and on their choosing and confirming halves,
:mod:`benchmarks.protocol`; AP50 of the self-test's composed frames otherwise); runtime ms/frame, timed frame by frame
in turn with the standard compile's bundle in one process, and its ratio to that bundle's time (the ratio is what to
compare: the machines are shared; ``--no-runtime`` leaves the timing out, for a point that fits the time at hand only
without compiling the standard one beside it); and compile time (render + train + export; a stage shared by several
points, such as the base renders, counts its full time for each; a stage interrupted and resumed counts every
attempt's time).

Work lives in ``--work``: renders, runs and bundles are keyed by the settings they depend on and reused; a finished
point is never recomputed (nor measured twice: the standard compile is every knob's reference value), and an unfinished
stage resumes its own work, so the sweep goes on after an interruption (a session's end) and runs a knob, or some of its
values, at a time (the whole sweep takes days on 2 cores). The settings include the network's heat-map layout: points
measured with the older 19-map layout (anatomical left/right) stay in the report, marked in its "heat maps" column,
until their knob runs again. Writes ``accuracy_vs_time.json``, ``accuracy_vs_time.md`` (with the values not measured
yet), ``accuracy_vs_time_<knob>.png`` and ``accuracy_vs_time_overview.png`` to ``--out``. The overview puts every
compile one can choose on one plot (the standard one once; the other training seeds are its repeats, shaded as the
spread between seeds), and draws the Pareto front, the points no other is both faster and more accurate than: what to
choose for a time budget, and which differences are noise."""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import re
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from functools import cached_property
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402

from benchmarks import results_folder  # noqa: E402
from benchmarks.protocol import HALVES, frame_halves, halves_cell  # noqa: E402
from vc.deploy.heatmaps import ANATOMICAL_CHANNELS, HEATMAP_CHANNELS  # noqa: E402
from vc.io import atomic_path, write_json  # noqa: E402
from vc.stages.config import PRESETS, TRAINING_COMPUTE  # noqa: E402

STANDARD = PRESETS["standard"]  # every point is this compile with one knob changed (its export aside: fp32)
HEARTBEAT_SECONDS = 30.0  # how much compile time a killed stage can lose from its record
TIMING_FRAMES = 30  # frames each bundle is timed on, in turn with the standard compile's bundle


@dataclass(frozen=True)
class Point:
    """One compile: the settings every stage depends on."""

    spp: int = STANDARD.render.spp
    effects: bool = True
    samples: int = STANDARD.render.samples
    # the network every knob was measured with; the default became fast-sep after (the separable knob compares
    # the two), and pinning it keeps the earlier points the standard compile's
    arch: str = "fast"
    width: int | None = None
    sb_units: int | None = None
    target_person_px: float | None = None  # None: the scene's own plan
    single_region: bool = False
    precision: str = "fp32"
    steps: int = STANDARD.train.steps
    heatmap_channels: int = HEATMAP_CHANNELS  # the trainer's output layout (19: anatomical pairs, before handedness)
    train_seed: int = 0
    photometry: str = "matched"  # see PHOTOMETRY; points stored before the knob were "off"
    # people placed alone, whatever the scene says (its own rate is a knob value like any other): every point
    # before the groups knob was measured so, and a scene that since says its people walk in groups
    # (examples/scenes/pets09_s2l1) must not turn the reference into another compile under the same cache keys
    group_rate: float = 0.0
    compute: str = "fp32"  # the trainer's compute settings, a name of TRAINING_COMPUTE
    clothing: str | None = None  # None: the scene's own priors.clothing

    def key(self, *fields: str) -> str:
        values = {name: getattr(self, name) for name in fields}
        return hashlib.sha256(json.dumps(values, sort_keys=True).encode()).hexdigest()[:12]

    def _rendered_as(self) -> tuple[str, ...]:
        # "off" keeps the keys of the renders made before photometric matching (they were rendered so), and the
        # scene's own group rate those made before the groups knob
        return (("photometry",) if self.photometry != "off" else ()) + (
            ("group_rate",) if self.group_rate else ()) + (
            ("clothing",) if self.clothing is not None else ())

    def render_key(self) -> str:
        return self.key("spp", "effects", "samples", "target_person_px", "single_region", *self._rendered_as())

    def train_key(self) -> str:
        seeded = ("train_seed",) if self.train_seed else ()  # seed 0 keeps the keys of runs made before the knob
        seeded += ("compute",) if self.compute != "fp32" else ()  # and fp32 those made before the compute knob
        return self.key("spp", "effects", "samples", "target_person_px", "single_region", "arch", "width",
                        "sb_units", "steps", "heatmap_channels", *seeded, *self._rendered_as())

    def bundle_key(self) -> str:
        return self.train_key() + "-" + self.precision


BASE = Point()
#: The photometry knob's values: what each leaves out of the matched renders.
PHOTOMETRY = {"off": "default sun, no camera effects", "light": "estimated light, no camera effects",
              "matched": "estimated light and every effect the scene calls for",
              "no sensor_noise": "matched less sensor noise", "no jpeg": "matched less compression",
              "no optical_blur": "matched less optical blur"}
#: Effects that are the renderer's geometry rather than the camera's: every photometry value keeps them.
GEOMETRIC_EFFECTS = ("lens_distortion", "shadows")
KNOBS: dict[str, dict[str, Point]] = {
    "spp": {str(v): replace(BASE, spp=v) for v in (4, 16, 64)},
    "effects": {"on": BASE, "off": replace(BASE, effects=False)},
    "samples": {str(v): replace(BASE, samples=v) for v in (1000, 2000, 5000, 20000, 50000)},
    "arch": {v: replace(BASE, arch=v) for v in ("fast", "fast-dw", "dense9")},
    # the preset's own value is the base point itself (same runs, not a second copy)
    "width": {"16": replace(BASE, width=16), "32": BASE, "64": replace(BASE, width=64)},
    "sb_units": {"1": replace(BASE, sb_units=1), "2": replace(BASE, sb_units=2), "3": BASE},
    "input": {f"{v} px": replace(BASE, target_person_px=v) for v in (40, 48, 64, 80)},
    "regions": {"per-region": BASE, "single (SPN-G)": replace(BASE, single_region=True)},
    "precision": {v: replace(BASE, precision=v) for v in ("fp32", "fp16", "int8")},
    "seed": {str(v): replace(BASE, train_seed=v) for v in (0, 1, 2)},
    "photometry": {v: BASE if v == "matched" else replace(BASE, photometry=v) for v in PHOTOMETRY},
    "groups": {"alone": BASE, **{f"rate 0.3, seed {seed}": replace(BASE, group_rate=0.3, train_seed=seed)
                                 for seed in (0, 1, 2)}},
    # the faster trainer against the standard compile's own seeds (the photometry seeds, 0.883-0.891)
    "compute": {"fp32": BASE, **{f"bf16 channels-last, seed {seed}": replace(BASE, compute="bf16 channels-last",
                                                                            train_seed=seed) for seed in (0, 1, 2)}},
    # what the people wear (priors.clothing), with the faster trainer of the compute knob and its seeds
    "clothing": {f"{clothing}, seed {seed}": replace(BASE, compute="bf16 channels-last", train_seed=seed,
                                                     clothing=clothing)
                 for clothing in ("mixed", "winter") for seed in (0, 1, 2)},
    # each SB unit's 13x13 as a 13x1 then a 1x13 (arch fast-sep: 0.65x the int8 network time), against the
    # default network's seeds with the same trainer (the clothing knob's mixed points)
    "separable": {f"{'on' if separable else 'off'}, seed {seed}": replace(
        BASE, compute="bf16 channels-last", train_seed=seed, arch="fast-sep" if separable else BASE.arch)
        for separable in (False, True) for seed in (0, 1, 2)},
    # groups on the default network: "alone" are the separable knob's "on" points (the same runs)
    "groups_sep": {f"{'rate 0.3' if grouped else 'alone'}, seed {seed}": replace(
        BASE, compute="bf16 channels-last", train_seed=seed, arch="fast-sep", group_rate=0.3 if grouped else 0.0)
        for grouped in (False, True) for seed in (0, 1, 2)},
    # the default network's stem (5x5 at half resolution, strided 3x3) against 4x4 patches (arch fast-patch), both
    # with people in groups as the PETS09 scene places them: "conv" are the groups_sep knob's "rate 0.3" runs
    "stem": {f"{stem}, seed {seed}": replace(BASE, compute="bf16 channels-last", train_seed=seed, group_rate=0.3,
                                             arch="fast-sep" if stem == "conv" else "fast-patch")
             for stem in ("conv", "patch") for seed in (0, 1, 2)},
}


@dataclass(frozen=True)
class SweepSettings:
    """Where the sweep works and what it measures on (the command line's arguments, typed)."""

    scene: Path
    work: Path
    dev_video: Path | None = None  # real frames; without them, AP50 of the self-test's composed frames
    dev_gt: Path | None = None
    dev_frames: str = "1:400:5"
    quiet: bool = False  # no progress bars from the stages
    paired_runtime: bool = True  # time each bundle in turn with the standard compile's


class Sweep:
    def __init__(self, settings: SweepSettings) -> None:
        self.settings, self.work = settings, settings.work
        self.scene_yaml = settings.scene.resolve()
        self.show_progress = not settings.quiet
        self.paired = settings.paired_runtime
        self._timing_frames: list[np.ndarray] | None = None

    def _timed(self, folder: Path, stage: Callable[[], object]) -> float:
        """Run ``stage`` for ``folder`` until it succeeds and remember how long it took in all (shared stages keep
        their time). A stage killed part-way (a session's end) resumes its own work when run again; its clock does
        too, from ``<folder>.partial-seconds.json``, which a heartbeat keeps within :data:`HEARTBEAT_SECONDS`."""
        record = folder.parent / f"{folder.name}.seconds.json"
        if record.is_file():
            return json.loads(record.read_text())["seconds"]
        partial = folder.parent / f"{folder.name}.partial-seconds.json"
        earlier = json.loads(partial.read_text())["seconds"] if partial.is_file() else 0.0
        start = time.perf_counter()

        def elapsed() -> float:
            return earlier + time.perf_counter() - start

        stopped = threading.Event()

        def heartbeat() -> None:
            while not stopped.wait(HEARTBEAT_SECONDS):
                write_json(partial, {"seconds": elapsed()})

        beating = threading.Thread(target=heartbeat, daemon=True)
        beating.start()
        try:
            stage()
        finally:
            stopped.set()
            beating.join()
            write_json(partial, {"seconds": elapsed()})
        seconds = elapsed()
        write_json(record, {"seconds": seconds})
        partial.unlink()
        return seconds

    def scene(self, point: Point) -> Path:
        """The scene YAML with the point's overrides (effects, region plan), its image and video paths absolute."""
        document = yaml.safe_load(self.scene_yaml.read_text())
        for key in ("image", "video"):  # the files the scene names, wherever the copy is written
            if key in document:
                path = Path(document[key])
                document[key] = str(path if path.is_absolute() else (self.scene_yaml.parent / path).resolve())
        regions = document.get("regions", "auto")
        regions = {"mode": regions} if isinstance(regions, str) else dict(regions)
        if point.single_region:
            regions["mode"] = "single"
        if point.target_person_px is not None:  # the knob plans every region at its size
            regions["target_person_px"] = point.target_person_px
            regions.pop("person_px_by_region", None)
        document["regions"] = regions
        if not point.effects:
            from vc.scenes.loader import load_scene

            distorted = not load_scene(self.scene_yaml).camera.distortion.is_identity
            document["effects"] = ["lens_distortion"] if distorted else []
        elif point.photometry != "matched":
            document.update(self.photometry_overrides(point.photometry))
        document["priors"] = {**document.get("priors", {}), "group_rate": point.group_rate}
        if point.clothing is not None:
            document["priors"] = {**document.get("priors", {}), "clothing": point.clothing}
        path = self.work / "scenes" / f"{point.render_key()}.yaml"
        with atomic_path(path) as temporary:
            temporary.write_text(yaml.safe_dump(document, sort_keys=False))
        return path

    @cached_property
    def planned_effects(self) -> list[str]:
        """The effects the scene's own plan turns on: the matched renders'."""
        from vc.render.plan import plan_render
        from vc.scenes.loader import load_scene
        from vc.scenes.regions import plan_regions

        scene = load_scene(self.scene_yaml)
        return [decision.name for decision in plan_render(scene, plan_regions(scene), time_costs=False).effects
                if decision.on]

    def photometry_overrides(self, photometry: str) -> dict:
        """Scene fields that turn the matched renders into ``photometry``'s (see :data:`PHOTOMETRY`)."""
        from vc.scenes.loader import load_scene
        from vc.scenes.schema import Lighting

        scene = load_scene(self.scene_yaml)
        geometric = [name for name in GEOMETRIC_EFFECTS
                     if name != "lens_distortion" or not scene.camera.distortion.is_identity]
        if photometry == "off":
            return {"lighting": Lighting().model_dump(), "effects": geometric}
        if photometry == "light":
            return {"effects": geometric}
        return {"effects": [name for name in self.planned_effects if name != photometry.removeprefix("no ")]}

    def same_photometry_as(self, photometry: str) -> str:
        """The first photometry value (in :data:`PHOTOMETRY` order) whose renders are the same as ``photometry``'s:
        matched less an effect the scene does not call for is matched, and matched less the only camera effect it
        calls for is the estimated light alone. Such a value is one compile, measured once."""
        def renders(value: str) -> tuple:
            overrides = self.photometry_overrides(value)  # "matched" leaves out nothing: the planned effects
            return frozenset(overrides["effects"]), json.dumps(overrides.get("lighting"), sort_keys=True)

        return next(value for value in PHOTOMETRY if renders(value) == renders(photometry))

    def compile(self, point: Point) -> tuple[dict[str, Path], dict[str, float]]:
        from vc.stages.config import ExportSettings, RenderSettings, TrainSettings
        from vc.stages.export import export
        from vc.stages.render import render
        from vc.stages.train import train

        scene = self.scene(point)
        renders = self.work / "renders" / point.render_key()
        run = self.work / "runs" / point.train_key()
        bundle = self.work / "bundles" / point.bundle_key()
        for folder in (renders, run, bundle):
            folder.parent.mkdir(parents=True, exist_ok=True)
        render_settings = RenderSettings(samples=point.samples, spp=point.spp)
        train_settings = TrainSettings(arch=point.arch, width=point.width, sb_units=point.sb_units, steps=point.steps,
                                       seed=point.train_seed, **TRAINING_COMPUTE[point.compute])
        seconds = {"render": self._timed(renders, lambda: render(scene, renders, render_settings,
                                                                 show_progress=self.show_progress)),
                   "train": self._timed(run, lambda: train(renders, run, train_settings,
                                                           show_progress=self.show_progress))}
        seconds["export"] = self._timed(bundle, lambda: export(run, bundle, ExportSettings(precision=point.precision),
                                                               show_progress=self.show_progress))
        return {"scene": scene, "renders": renders, "bundle": bundle}, seconds

    def as_compiled(self, point: Point) -> Point:
        """``point`` with a knob value that is the scene's own setting left unset: the same compile as the standard
        one, so it shares its keys (the demo scene plans 80 px people: ``input 80 px`` is the standard point, not a
        copy; PETS's people wear the mixed clothing: ``mixed`` is the compute knob's point). A scene that sizes some
        regions on their own (PETS: r1 at 48 px, the rest at 42) equals no input point."""
        from vc.scenes.loader import load_scene

        scene = load_scene(self.scene_yaml)
        if point.target_person_px == scene.regions.target_person_px and not scene.regions.person_px_by_region:
            point = replace(point, target_person_px=None)
        if point.clothing == scene.priors.clothing:
            point = replace(point, clothing=None)
        return point

    def measure(self, knob: str, value: str, point: Point) -> dict:
        point = self.as_compiled(point)
        points = self.work / "points"
        path = points / knob / f"{value.replace(' ', '_')}-{point.bundle_key()}.json"
        if path.is_file():
            result = json.loads(path.read_text())
            if self.paired and "runtime_vs_base" not in result:  # measured without the paired timing: add it now
                result.update(self.paired_runtime(self.work / "bundles" / point.bundle_key()))
                write_json(path, result)
            return result
        if knob == "photometry" and (same := self.same_photometry_as(value)) != value:
            result = self.measure(knob, same, KNOBS[knob][same]) | {"knob": knob, "value": value, "same_as": same}
            write_json(path, result)
            return result
        # the same compile measured under another knob (the standard one is every knob's reference value) is this
        # measurement: the evaluation is deterministic, so it is not run again
        elsewhere = sorted(points.glob(f"*/*-{point.bundle_key()}.json"))
        if elsewhere:
            result = json.loads(elsewhere[0].read_text()) | {"knob": knob, "value": value}
            write_json(path, result)
            return self.measure(knob, value, point)
        print(f"{knob} = {value}: compile {point.bundle_key()} (stages done before are reused), then measure",
              flush=True)
        paths, seconds = self.compile(point)
        manifest = json.loads((paths["bundle"] / "manifest.json").read_text())
        held_out = [region["held_out_accuracy"][region["precision"]] for region in manifest["regions"]]
        result = {"knob": knob, "value": value, "point": asdict(point), "compile_seconds": seconds,
                  "compile_minutes": sum(seconds.values()) / 60,
                  "synthetic_ap50": float(np.mean([r["ap50"] for r in held_out])),
                  "synthetic_pckh": float(np.mean([r["pckh"] or 0.0 for r in held_out]))}
        result.update(self.real(paths["bundle"], knob, value) if self.settings.dev_video else self.composed(**paths))
        if self.paired:
            result.update(self.paired_runtime(paths["bundle"]))
        write_json(path, result)
        return result

    def paired_runtime(self, bundle: Path) -> dict:
        """Median ms/frame of ``bundle`` and of the standard compile's bundle, timed in turn frame by frame in this
        process: a shared machine's load (it swung 41–53 ms for one bundle within minutes) hits both alike, so
        their ratio holds where a lone time does not. A load that takes the cores frame by frame (a training run
        beside it) breaks even the ratio: the same bundle once timed 0.22x itself over 4 frames. Compiles the
        standard point first if it is missing."""
        from vc.deploy.runtime import Runtime

        paths, _ = self.compile(BASE)
        frames = self.timing_frames()
        runtimes = [Runtime(bundle), Runtime(paths["bundle"])]
        times: list[list[float]] = [[], []]
        for runtime in runtimes:
            runtime(frames[0])  # warm-up: the sessions' first run allocates
        for frame in frames:
            for runtime, measured in zip(runtimes, times, strict=True):
                start = time.perf_counter()
                runtime(frame)
                measured.append((time.perf_counter() - start) * 1e3)
        point_ms, base_ms = (float(np.median(measured)) for measured in times)
        return {"runtime_ms": point_ms, "base_runtime_ms": base_ms, "runtime_vs_base": point_ms / base_ms}

    def timing_frames(self) -> list[np.ndarray]:
        """The frames every bundle is timed on: the first :data:`TIMING_FRAMES` development frames, or without
        them frames composed of the standard point's held-out renders on the scene's background."""
        if self._timing_frames is None:
            if self.settings.dev_video:
                from vc.deploy.frames import FrameRange, FrameSource

                source = FrameSource(self.settings.dev_video, FrameRange.parse(self.settings.dev_frames))
                self._timing_frames = [frame.image for frame in itertools.islice(source, TIMING_FRAMES)]
            else:
                from vc.evaluation.selftest import composite_frame
                from vc.io import read_image
                from vc.render.dataset import open_region, read_manifest
                from vc.scenes.loader import load_scene

                renders = self.work / "renders" / BASE.render_key()
                regions = [open_region(renders, name) for name in read_manifest(renders)["regions"]]
                background = read_image(load_scene(self.scene(BASE)).image_path)
                self._timing_frames = [composite_frame(background, regions, index).image
                                       for index in range(TIMING_FRAMES)]
        return self._timing_frames

    def real(self, bundle: Path, knob: str, value: str) -> dict:
        """AP50 on the development frames, and on their choosing and confirming halves, each half run on its own
        as a decision is measured (:mod:`benchmarks.protocol`)."""
        from vc.deploy.frames import FrameRange
        from vc.evaluation.mot import read_mot_boxes
        from vc.evaluation.real_video import OURS, OURS_SINGLE_FRAME, EvaluationRequest, evaluate_bundle

        output = self.work / "evals" / knob / value.replace(" ", "_")
        frames = FrameRange.parse(self.settings.dev_frames)

        def detectors(selection: FrameRange, folder: Path) -> dict:
            request = EvaluationRequest(bundle=bundle, video=self.settings.dev_video,
                                        ground_truth=self.settings.dev_gt, output=folder, frames=selection, hog=False)
            return evaluate_bundle(request, show_progress=self.show_progress).metrics["detectors"]

        whole = detectors(frames, output)
        # Each frame on its own, as every point before tracking was measured; tracked beside it.
        result = {"real_ap50": whole[OURS_SINGLE_FRAME]["ap50"], "real_ap50_tracked": whole[OURS]["ap50"],
                  "eval_runtime_ms": whole[OURS_SINGLE_FRAME]["ms_per_frame"]["median"]}
        for half, selection in frame_halves(frames, max(read_mot_boxes(self.settings.dev_gt))).items():
            found = detectors(selection, output / half)
            result |= {f"real_ap50_{half}": found[OURS_SINGLE_FRAME]["ap50"],
                       f"real_ap50_tracked_{half}": found[OURS]["ap50"]}
        return result

    def composed(self, scene: Path, renders: Path, bundle: Path) -> dict:
        from vc.deploy.runtime import Runtime
        from vc.evaluation.selftest import self_test
        from vc.io import read_image
        from vc.render.dataset import open_region, read_manifest
        from vc.scenes.loader import load_scene

        regions = [open_region(renders, name) for name in read_manifest(renders)["regions"]]
        result = self_test(Runtime(bundle), read_image(load_scene(scene).image_path), regions, 20)
        return {"composed_ap50": result.ap50}


# where a label may sit around its point, in points: above right first, then above left, below, and further out
LABEL_OFFSETS = ((3, 3, "left", "bottom"), (-3, 3, "right", "bottom"), (3, -3, "left", "top"),
                 (-3, -3, "right", "top"), (3, 10, "left", "bottom"), (3, -10, "left", "top"))
MARKER_RADIUS = 2.5  # points: a label this close to another point's centre would cover its marker


def annotate_apart(axis: plt.Axes, labels: list[tuple[str, float, float]]) -> None:
    """Label each point at the first of :data:`LABEL_OFFSETS` where its text stays inside the axes and covers no
    label placed before it, no labelled point's marker and not the legend (points of similar time and accuracy
    would print their names over each other). Call it once the figure's layout is final: overlaps are judged in
    display space."""
    renderer = axis.figure.canvas.get_renderer()
    frame = axis.get_window_extent(renderer)
    radius = renderer.points_to_pixels(MARKER_RADIUS)
    centres = axis.transData.transform([(x, y) for _, x, y in labels]) if labels else []
    taken = [Bbox.from_extents(cx - radius, cy - radius, cx + radius, cy + radius) for cx, cy in centres]
    legend = axis.get_legend()
    taken += [legend.get_window_extent(renderer)] if legend else []

    def place(text: str, x: float, y: float, offset: tuple[int, int, str, str]) -> tuple[plt.Annotation, Bbox]:
        dx, dy, horizontal, vertical = offset
        label = axis.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=7,
                              ha=horizontal, va=vertical)
        return label, label.get_window_extent(renderer)

    for text, x, y in labels:
        for offset in LABEL_OFFSETS:
            label, extent = place(text, x, y, offset)
            inside = frame.contains(extent.x0, extent.y0) and frame.contains(extent.x1, extent.y1)
            if inside and not any(extent.overlaps(other) for other in taken):
                break
            label.remove()
        else:  # crowded on every side: the first place, overlapping
            _, extent = place(text, x, y, LABEL_OFFSETS[0])
        taken.append(extent)


def _plot(knob: str, points: list[dict], out: Path) -> None:
    metrics = [(name, label) for name, label in (("synthetic_ap50", "synthetic AP50"),
                                                 ("synthetic_pckh", "synthetic PCKh@0.5"),
                                                 ("real_ap50", "real AP50"), ("composed_ap50", "composed AP50"))
               if any(name in point for point in points)]
    figure, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    # runtime as the ratio to the standard bundle timed in turn with it: lone ms from different hours don't compare
    labels: dict[plt.Axes, list[tuple[str, float, float]]] = {axis: [] for axis in axes}
    for axis, x_name, x_label in ((axes[0], "compile_minutes", "compile time (min, 2 cores)"),
                                  (axes[1], "runtime_vs_base", "runtime / standard compile's (timed in turn)")):
        for name, label in metrics:
            shown = [point for point in points if name in point and x_name in point]
            axis.plot([point[x_name] for point in shown], [point[name] for point in shown], "o-", label=label)
            labels[axis] += [(point["value"], point[x_name], point[name]) for point in shown]
        # times from zero (the ratio between points is what matters), with room for the rightmost labels (a knob
        # measured only with --no-runtime has no runtime to show)
        right = 1.15 * max(point.get(x_name, 0.0) for point in points) or 1.0
        axis.set(xlabel=x_label, ylim=(0, 1.08), xlim=(0, right))
        axis.grid(alpha=0.3)
    base_ms = [point["base_runtime_ms"] for point in points if "base_runtime_ms" in point]
    if base_ms:  # the same ratios in ms, at the standard bundle's median time over these points' pairings
        standard_ms = float(np.median(base_ms))
        top = axes[1].secondary_xaxis("top", functions=(lambda ratio: ratio * standard_ms,
                                                        lambda ms: ms / standard_ms))
        top.set_xlabel(f"ms/frame (2 cores; standard {standard_ms:.1f} ms)", fontsize=8)
    axes[0].set_ylabel("accuracy")
    axes[0].legend(fontsize=8, loc="lower left")  # accuracies sit high: the corner stays clear
    figure.suptitle(f"knob: {knob}")
    figure.tight_layout()
    for axis, axis_labels in labels.items():
        annotate_apart(axis, merge_coinciding(axis_labels))
    figure.savefig(out / f"accuracy_vs_time_{knob}.png", dpi=120)
    plt.close(figure)


def merge_points(knob: str, earlier: list[dict], fresh: list[dict]) -> list[dict]:
    """The knob's points in :data:`KNOBS` order: fresh measurements, else the earlier ones (values not re-run)."""
    by_value = {point["value"]: point for point in earlier} | {point["value"]: point for point in fresh}
    return [by_value[value] for value in KNOBS[knob] if value in by_value]


def pending_values(results: dict[str, list[dict]]) -> dict[str, list[str]]:
    """Per knob, the values that have no measurement yet (a partial sweep says what it lacks)."""
    pending = {knob: [value for value in values if value not in {p["value"] for p in results.get(knob, [])}]
               for knob, values in KNOBS.items()}
    return {knob: values for knob, values in pending.items() if values}


def _layout(point: dict) -> int:
    """The heat-map layout a measured point was trained with (points stored before the field had the older one)."""
    return point["point"].get("heatmap_channels", ANATOMICAL_CHANNELS)


def _photometry(point: dict) -> str:
    """The renders' photometry of a measured point (points stored before the knob had none: "off")."""
    return point["point"].get("photometry", "off")


def identity(point: dict) -> str:
    """The compile a measured point stands for (the standard point is measured under several knobs)."""
    return Point(**{**asdict(BASE), **point["point"], "heatmap_channels": _layout(point),
                    "photometry": _photometry(point)}).bundle_key()


def distinct_compiles(results: dict[str, list[dict]]) -> list[dict]:
    """Every compile measured once, named ``standard`` or by its knob and value, in the current heat-map layout
    (the older layout's points are not comparable with the rest)."""
    standard = BASE.bundle_key()
    distinct: dict[str, dict] = {}
    for knob, points in results.items():
        for point in points:
            if _layout(point) != HEATMAP_CHANNELS:
                continue
            compiled = identity(point)
            name = "standard" if compiled == standard else f"{knob} {point['value']}"
            distinct.setdefault(compiled, point | {"name": name})
    return list(distinct.values())


#: A value measured with several training seeds ("winter, seed 1"): the setting, then the seed.
SEEDED_VALUE = re.compile(r"^(?P<setting>.+), seed (?P<seed>\d+)$")
#: What a setting measured with several seeds reports: each the mean over its seeds.
SEED_MEAN_FIELDS = ("real_ap50", "real_ap50_tracked",
                    *(f"real_ap50{kind}_{half}" for kind in ("", "_tracked") for half in HALVES),
                    "composed_ap50", "synthetic_ap50", "synthetic_pckh", "compile_minutes", "runtime_ms",
                    "runtime_vs_base")


def choices(results: dict[str, list[dict]]) -> list[dict]:
    """The distinct compiles a user can pick from. Another training seed is a repeat of a compile, not a choice (no
    one knows beforehand which seed is lucky): the seed knob is drawn as the noise band and kept off the front, and
    a setting measured with several seeds ("winter, seed 0/1/2") is one point, the mean over its seeds."""
    kept: list[dict] = []
    seeded: dict[str, list[dict]] = {}
    for point in distinct_compiles(results):
        match = SEEDED_VALUE.match(point["name"])
        if match:
            seeded.setdefault(match["setting"], []).append(point)
        elif not point["point"].get("train_seed"):
            kept.append(point)
    for setting, points in seeded.items():
        means = {field: float(np.mean([p[field] for p in points])) for field in SEED_MEAN_FIELDS
                 if all(field in p for p in points)}
        kept.append(points[0] | means | {"name": f"{setting} ({len(points)} seeds)" if len(points) > 1 else setting,
                                         "seeds": len(points)})
    return kept


def pareto_front(points: list[dict], time_name: str, accuracy_name: str) -> list[dict]:
    """The points that no other beats, by time ascending: each is more accurate than every faster or as fast one
    (a tie in both keeps the first)."""
    ranked = sorted((p for p in points if time_name in p and accuracy_name in p),
                    key=lambda p: (p[time_name], -p[accuracy_name]))
    front: list[dict] = []
    for point in ranked:
        if not front or point[accuracy_name] > front[-1][accuracy_name]:
            front.append(point)
    return front


def _accuracy_name(points: list[dict]) -> tuple[str, str]:
    if any("real_ap50" in point for point in points):
        return "real_ap50", "real AP50"
    return "composed_ap50", "composed AP50"


def _seed_spread(results: dict[str, list[dict]], accuracy_name: str) -> tuple[float, float] | None:
    measured = [point[accuracy_name] for point in results.get("seed", []) if accuracy_name in point]
    return (min(measured), max(measured)) if len(measured) > 1 else None


def merge_coinciding(labels: list[tuple[str, float, float]]) -> list[tuple[str, float, float]]:
    """One label per spot: the texts of points within 2 % of the plot's spans of an earlier one join its label (the
    standard point and fp16 share accuracy and time, and three names around one marker don't say which is which)."""
    xs, ys = [x for _, x, _ in labels], [y for _, _, y in labels]
    tolerance_x = 0.02 * max(max(xs, default=0.0), 1e-9)
    tolerance_y = 0.02 * max(max(ys, default=0.0) - min(ys, default=0.0), 1e-9)
    spots: dict[tuple[float, float], list[str]] = {}
    for text, x, y in labels:
        spot = next((spot for spot in spots if abs(spot[0] - x) <= tolerance_x and abs(spot[1] - y) <= tolerance_y),
                    (x, y))
        spots.setdefault(spot, []).append(text)
    return [(" / ".join(texts), x, y) for (x, y), texts in spots.items()]


def _plot_overview(results: dict[str, list[dict]], out: Path) -> None:
    points = choices(results)
    accuracy_name, accuracy_label = _accuracy_name(points)
    spread = _seed_spread(results, accuracy_name)
    figure, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    labels: dict[plt.Axes, list[tuple[str, float, float]]] = {}
    for axis, time_name, time_label in ((axes[0], "compile_minutes", "compile time (min, 2 cores)"),
                                        (axes[1], "runtime_vs_base", "runtime / standard compile's (timed in turn)")):
        shown = [point for point in points if time_name in point and accuracy_name in point]
        labels[axis] = [(point["name"], point[time_name], point[accuracy_name]) for point in shown]
        front = pareto_front(shown, time_name, accuracy_name)
        if spread:  # differences inside this band are what another training seed alone gives
            axis.axhspan(*spread, color="0.85", label="training-seed spread")
        axis.scatter([p[time_name] for p in shown], [p[accuracy_name] for p in shown], color="tab:blue", s=18)
        # the front as a staircase: the best accuracy reachable within each time
        axis.step([p[time_name] for p in front], [p[accuracy_name] for p in front], where="post", color="tab:red",
                  label="best for its time (Pareto front)")
        axis.set(xlabel=time_label, xlim=(0, 1.25 * max((p[time_name] for p in shown), default=1.0)))
        axis.grid(alpha=0.3)
    axes[0].set_ylabel(accuracy_label)
    axes[0].legend(fontsize=8, loc="lower right")
    figure.suptitle(f"every setting measured: {accuracy_label} against compile time and runtime "
                    "(grey: the spread of training seeds)")
    figure.tight_layout()
    for axis, axis_labels in labels.items():  # once the layout is final: placing them measures the text
        annotate_apart(axis, merge_coinciding(axis_labels))
    figure.savefig(out / "accuracy_vs_time_overview.png", dpi=120)
    plt.close(figure)


def _overview_lines(results: dict[str, list[dict]]) -> list[str]:
    points = choices(results)
    accuracy_name, accuracy_label = _accuracy_name(points)
    lines = []
    for time_name, time_label, shown in (("runtime_vs_base", "runtime", "{:.2f}x"),
                                         ("compile_minutes", "compile time", "{:.1f} min")):
        front = pareto_front(points, time_name, accuracy_name)
        if front:
            listed = ", ".join(f"{p['name']} ({p[accuracy_name]:.3f} at {shown.format(p[time_name])})" for p in front)
            lines.append(f"Best {accuracy_label} for its {time_label} (Pareto front): {listed}.")
    spread = _seed_spread(results, accuracy_name)
    if spread:
        lines.append(f"Training seeds alone span {accuracy_label} {spread[0]:.3f}–{spread[1]:.3f}: a difference "
                     f"smaller than {spread[1] - spread[0]:.3f} is within the noise.")
    return lines


def _report(results: dict[str, list[dict]], out: Path) -> None:
    results = {knob: results[knob] for knob in KNOBS if knob in results}  # the order of the module's docstring
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "accuracy_vs_time.json", results)
    lines = ["| knob | value | heat maps | photometry | compile min | synthetic AP50 | synthetic PCKh | real AP50 | "
             "real AP50 choosing / confirming | runtime ms/frame | runtime / standard |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for knob, points in results.items():
        for p in points:
            real = f"{p['real_ap50']:.3f}" if "real_ap50" in p else "—"
            halves = halves_cell(p)
            ms = f"{p['runtime_ms']:.1f}" if "runtime_ms" in p else "—"
            ratio = f"{p['runtime_vs_base']:.2f}" if "runtime_vs_base" in p else "—"
            lines.append(f"| {knob} | {p['value']} | {_layout(p)} | {_photometry(p)} | {p['compile_minutes']:.1f} | "
                         f"{p['synthetic_ap50']:.3f} | {p['synthetic_pckh']:.3f} | {real} | {halves} | {ms} | "
                         f"{ratio} |")
        _plot(knob, points, out)
    _plot_overview(results, out)
    lines += ["", *_overview_lines(results)]
    pending = pending_values(results)
    if pending:
        listed = "; ".join(f"{knob} {', '.join(values)}" for knob, values in pending.items())
        lines += ["", f"Not measured yet: {listed}."]
    with atomic_path(out / "accuracy_vs_time.md") as temporary:
        temporary.write_text("\n".join(lines) + "\n")


def build_parser(knob: str | None = None) -> argparse.ArgumentParser:
    """The sweep's arguments; with ``knob`` the sweep runs that one knob and ``--knob`` is not asked for."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", type=Path, required=True)
    if knob is None:
        parser.add_argument("--knob", nargs="+", choices=list(KNOBS), required=True)
    else:
        parser.set_defaults(knob=[knob])
    parser.add_argument("--value", nargs="+", metavar="VALUE",
                        help="measure only these values of the one --knob (as the table names them); its other values "
                             "keep their earlier results. For the points that take hours (20k/50k samples, width 64)")
    parser.add_argument("--work", type=Path, default=Path("out/accuracy_vs_time"))
    parser.add_argument("--dev-video", type=Path)
    parser.add_argument("--dev-gt", type=Path)
    parser.add_argument("--dev-frames", default="1:400:5")
    parser.add_argument("--quiet", action="store_true", help="no progress bars from the stages")
    parser.add_argument("--no-runtime", action="store_true",
                        help="leave out the paired runtime timing, which needs the standard compile's bundle "
                             "(about 55 min on 2 cores where the work dir lacks it); with --dev-video the point "
                             "keeps vc-eval's own ms/frame, and a later run without this flag adds the timing "
                             "while the work dir keeps its bundle")
    parser.add_argument("--out", type=Path, default=results_folder("accuracy_vs_time"))
    return parser


def run(parser: argparse.ArgumentParser, argv: list[str] | None = None) -> argparse.Namespace:
    """Parse, check, measure every requested point and rewrite the report; returns the arguments."""
    args = parser.parse_args(argv)
    if bool(args.dev_video) != bool(args.dev_gt):
        parser.error("--dev-video and --dev-gt go together")
    if args.value:
        if len(args.knob) != 1:
            parser.error("--value needs exactly one --knob")
        knob, = args.knob
        unknown = [value for value in args.value if value not in KNOBS[knob]]
        if unknown:
            parser.error(f"--value {', '.join(unknown)}: {knob} has the values {', '.join(KNOBS[knob])}")
    sweep = Sweep(SweepSettings(scene=args.scene, work=args.work, dev_video=args.dev_video, dev_gt=args.dev_gt,
                                dev_frames=args.dev_frames, quiet=args.quiet, paired_runtime=not args.no_runtime))
    previous = args.out / "accuracy_vs_time.json"
    for knob in args.knob:
        fresh = [sweep.measure(knob, value, point) for value, point in KNOBS[knob].items()
                 if not args.value or value in args.value]
        # read after measuring, which takes hours: another sweep may have reported its own knobs meanwhile
        results = json.loads(previous.read_text()) if previous.is_file() else {}
        results[knob] = merge_points(knob, results.get(knob, []), fresh)
        _report(results, args.out)
        print(f"{knob}: " + ", ".join(f"{p['value']} {p['synthetic_ap50']:.3f}" for p in results[knob]), flush=True)
    return args


def main() -> None:
    run(build_parser())


if __name__ == "__main__":
    main()
