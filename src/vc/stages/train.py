"""The train stage: one network per region of a rendered dataset, checkpointed in a run folder, with the held-out
metrics of every region merged into ``RUN/metrics.json``."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import torch

from vc.deploy.crop_pose import MIN_READ_HEIGHT_PX
from vc.errors import InputError
from vc.evaluation.plots import plot_precision_recall
from vc.io import atomic_path, write_json
from vc.model.camera_range import plan_lines
from vc.model.crop_pose import (
    CROP_POSE_MODEL,
    CROP_POSE_REPORT,
    MIN_CROP_POSE_CROPS,
    MIN_TALL_SHARE,
    SAMPLES_SEEN,
    TRAINED_HEIGHT_SHARE,
    frame_heights,
    train_crop_pose,
)
from vc.model.crop_pose import dataset_crops as crop_pose_crops
from vc.model.crop_precision import keypoints_at_int8
from vc.model.export import export_crop_pose, export_facing
from vc.model.facing import (
    FACING_MODEL,
    FACING_REPORT,
    MEMBERS,
    MIN_FACING_CROPS,
    dataset_crops,
    train_distilled_facing,
    train_face_turn,
    train_head_colours,
)
from vc.model.trainer import RegionResult, TrainConfig, data_workers, select_device
from vc.render.dataset import read_manifest
from vc.stages.config import TrainSettings
from vc.stages.executors import Executor, InProcess, LocalProcesses, RegionTask, train_region

METRICS = "metrics.json"


@dataclass
class TrainingJob:
    dataset: Path
    regions: list[str]
    settings: TrainSettings
    config: TrainConfig
    device: torch.device
    workers: int  # data-loading processes per region

    def run(self, run: Path, show_progress: bool = True, executor: Executor | None = None) -> list[RegionResult]:
        """Train (or resume) every region, evaluate each on its held-out renders, and write ``RUN/metrics.json``
        (regions trained into ``run`` before stay in it) and ``RUN/precision_recall.png``. ``executor``: where
        the regions train (in turn in this process, with progress bars, by default; as parallel tasks on a
        cluster, silently). Worker processes of this machine train in turn here too: one training already takes
        the machine (every core, its data loaders, the GPU), which one renderer does not."""
        executor = InProcess() if executor is None or isinstance(executor, LocalProcesses) else executor
        here = isinstance(executor, InProcess)
        tasks = [RegionTask(self.dataset, name, self.config, run, self.workers, show_progress and here)
                 for name in self.regions]
        by_index = dict(executor.map_unordered(train_region, tasks))
        results = [by_index[index] for index in range(len(tasks))]
        manifest = read_manifest(self.dataset)
        metrics = _merged_metrics(run, manifest, self.dataset, self.device.type, results)
        if self.settings.facing:
            metrics["facing"] = train_facing_model(self.dataset, run, self.config.seed, show_progress and here)
        metrics["crop_pose"] = train_crop_pose_model(self.dataset, run, self.config.seed, self.settings.crop_pose,
                                                     show_progress and here)
        write_json(run / METRICS, metrics)
        plot_precision_recall({r.region: r.evaluation.evaluation for r in results}, run / "precision_recall.png",
                              f"{manifest['scene']}: held-out synthetic")
        return results


    def camera_range_plan(self) -> list[str]:
        """What the windows vary over, each variation's reason, and its cost (:func:`plan_lines`)."""
        manifest = read_manifest(self.dataset)
        regions = {name: manifest["regions"][name] for name in self.regions}
        return plan_lines(manifest, regions, self.config.camera_range)


def prepare_training(dataset: Path, settings: TrainSettings, region_names: list[str] | None = None) -> TrainingJob:
    """The regions to train (all of the dataset's by default), the full training config and the device."""
    device = select_device()
    workers = data_workers(device) if settings.workers == "auto" else settings.workers
    return TrainingJob(dataset, _regions(dataset, region_names), settings, settings.train_config(), device, workers)


def train(dataset: Path, run: Path, settings: TrainSettings, region_names: list[str] | None = None,
          show_progress: bool = True) -> list[RegionResult]:
    """The whole stage: :func:`prepare_training` then :meth:`TrainingJob.run`."""
    return prepare_training(dataset, settings, region_names).run(run, show_progress)


def train_facing_model(dataset: Path, run: Path, seed: int, show_progress: bool = True) -> dict:
    """Train the facing model on ``dataset``'s renders into ``RUN/facing.onnx`` (:mod:`vc.model.facing`): the facing
    classifier and, beside it, the face turn and the head's colours. Or keep the one an earlier invocation trained
    there on the same renders with the same seed; what it measured (``RUN/facing.json``), or why there is none."""
    model, report = run / FACING_MODEL, run / FACING_REPORT
    manifest = read_manifest(dataset)
    trained_on = {"scene_hash": manifest["scene_hash"], "dataset_settings": manifest.get("settings"), "seed": seed,
                  "reads": ["facing", "face turn", "head colours"],  # one that reads less is trained again
                  "facing_members": MEMBERS}  # one not distilled from as many is trained again
    if model.is_file() and report.is_file():
        earlier = json.loads(report.read_text())
        if earlier.get("trained_on") == trained_on:
            return earlier
    train, held_out = dataset_crops(dataset)
    if len(train.facing) < MIN_FACING_CROPS:
        return {"skipped": f"{len(train.facing)} rendered people face the camera or away from it; the facing model "
                           f"needs {MIN_FACING_CROPS} or more (render more samples)"}
    result = train_distilled_facing(train.facing, held_out.facing, seed, show_progress=show_progress)
    head = train_head_colours(train.facing, held_out.facing, seed)
    turn = None
    if len(train.turn) >= MIN_FACING_CROPS:
        turn = train_face_turn(train.turn, held_out.turn, seed, show_progress=show_progress)
    with atomic_path(model) as temporary:
        temporary.write_bytes(export_facing(result.net, None if turn is None else turn.net, head.net))
    turned = turn.to_dict() if turn is not None else {
        "skipped": f"{len(train.turn)} rendered people have their nose and ears labelled; the face turn needs "
                   f"{MIN_FACING_CROPS} or more"}
    measured = {**result.to_dict(), "face_turn": turned, "head_colours": head.to_dict(), "trained_on": trained_on}
    write_json(report, measured)
    return measured


def train_crop_pose_model(dataset: Path, run: Path, seed: int, wanted: bool | Literal["auto"] = True,
                          show_progress: bool = True) -> dict:
    """Train the keypoint model on ``dataset``'s renders into ``RUN/crop_pose.onnx`` (:mod:`vc.model.crop_pose`; at
    int8 where it holds, :mod:`vc.model.crop_precision`), or
    keep the one an earlier invocation trained there on the same renders with the same seed; what it measured
    (``RUN/crop_pose.json``), or why there is none. ``wanted``: "auto" trains it where most of the scene's people
    are tall enough to be read (:func:`crop_pose_not_called_for`). A run without one keeps none from before, which
    an export would ship."""
    model, report = run / CROP_POSE_MODEL, run / CROP_POSE_REPORT
    reason = ("not asked for (train.crop_pose: false)" if wanted is False
              else crop_pose_not_called_for(dataset) if wanted == "auto" else None)
    manifest = read_manifest(dataset)
    trained_on = {"scene_hash": manifest["scene_hash"], "dataset_settings": manifest.get("settings"), "seed": seed,
                  "precision": "int8 where it holds",  # one exported fp32 alone is trained again
                  "crops_seen": SAMPLES_SEEN}  # one trained on a shorter schedule too
    if reason is None and model.is_file() and report.is_file():
        earlier = json.loads(report.read_text())
        if earlier.get("trained_on") == trained_on:
            return earlier
    if reason is None:
        train, held_out = crop_pose_crops(dataset, seed, TRAINED_HEIGHT_SHARE * MIN_READ_HEIGHT_PX)
        if len(train) < MIN_CROP_POSE_CROPS:
            reason = (f"{len(train)} rendered people are seen whole and {TRAINED_HEIGHT_SHARE * MIN_READ_HEIGHT_PX:g}"
                      f" px or taller in the frame; the keypoint model needs {MIN_CROP_POSE_CROPS} or more")
    if reason is not None:
        model.unlink(missing_ok=True)
        report.unlink(missing_ok=True)
        return {"skipped": reason}
    result = train_crop_pose(train, held_out, seed, show_progress=show_progress)
    chosen = keypoints_at_int8(export_crop_pose(result.net), train, held_out, seed)
    with atomic_path(model) as temporary:
        temporary.write_bytes(chosen.model)
    measured = {**result.to_dict(), "precision": chosen.precision,
                "held_out_pckh_by_precision": {precision: None if value is None else round(value, 4)
                                               for precision, value in chosen.measured.items()},
                "trained_on": trained_on}
    write_json(report, measured)
    return measured


def crop_pose_not_called_for(dataset: Path) -> str | None:
    """Why a compile left to decide trains no keypoint model for ``dataset``'s scene, or None where it does: fewer
    than :data:`~vc.model.crop_pose.MIN_TALL_SHARE` of its whole rendered people stand
    :data:`~vc.deploy.crop_pose.MIN_READ_HEIGHT_PX` or taller in the frame, the only ones the model reads."""
    heights = frame_heights(dataset)
    share = float((heights >= MIN_READ_HEIGHT_PX).mean()) if len(heights) else 0.0
    if share >= MIN_TALL_SHARE:
        return None
    return (f"{share:.0%} of the scene's whole rendered people stand {MIN_READ_HEIGHT_PX:g} px or taller in the "
            f"frame, the only ones the keypoint model reads; it is trained where {MIN_TALL_SHARE:.0%} or more do "
            "(train.crop_pose: true trains it anyway)")


def read_metrics(run: Path) -> dict:
    """``RUN/metrics.json`` as the stage wrote it."""
    return json.loads((run / METRICS).read_text())


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
            previous = read_metrics(run).get("regions", {})
        except (OSError, json.JSONDecodeError):
            previous = {}
    regions = {**previous, **{result.region: result.to_dict() for result in results}}
    return {"scene": manifest["scene"], "scene_hash": manifest["scene_hash"], "dataset": str(dataset),
            "device": device, "regions": dict(sorted(regions.items()))}
