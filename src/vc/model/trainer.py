"""Training one region's ScenePoseNet: the loop, checkpoints that can be resumed byte for byte, and the held-out
evaluation written as ``metrics.json`` material and a precision-recall curve.

A run folder holds ``checkpoints/<region>.pt`` (weights, optimiser, schedule, step, loss history, the full
training config, the network config and the scene and region it belongs to) and ``<region>/`` (the
precision-recall and loss curves). Checkpoints are written through a temporary name, so an interrupted run
resumes from the last complete one; every batch is a pure function of (seed, step) (:class:`TrainingStream`), so
the resumed run ends with the same weights as one that never stopped.
"""

from __future__ import annotations

import hashlib
import io
import math
import os
import pickle
import time
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np
import torch
from pydantic import TypeAdapter, ValidationError
from torch.torch_version import TorchVersion
from torch.utils.data import DataLoader
from tqdm import tqdm

from vc.calibration.camera import camera_from_dict
from vc.cores import cpu_facts, usable_cores
from vc.deploy.decode import DecodeConfig, RetiredSetting, stored_decode_fields
from vc.deploy.heatmaps import HEATMAP_CHANNELS
from vc.errors import InputError, StageError
from vc.evaluation.plots import plot_precision_recall, plot_training_curve
from vc.io import atomic_path
from vc.model.camera_range import CameraRange, camera_life_of
from vc.model.codec import CodecConfig, expected_height_map
from vc.model.config import DEFAULT_ARCH, NetworkConfig, network_config, stored_network_fields
from vc.model.data import Augmentation, CropPolicy, TrainingStream
from vc.model.held_out import RegionEvaluation, evaluate_network
from vc.model.loss import LossWeights, scene_pose_loss
from vc.model.network import ScenePoseNet
from vc.render.dataset import RegionData

#: 2: the content carries its own digest (``content_sha256``, :func:`content_digest`).
CHECKPOINT_FORMAT = 2
#: 1 differs from 2 only by the missing digest: such checkpoints are read unchecked.
READABLE_CHECKPOINT_FORMATS = (1, 2)
CHECKPOINT_KIND = "vc-train checkpoint"
#: Loss values kept for the training curve: one per this many steps (mean of the steps in between).
HISTORY_EVERY = 10


@dataclass(frozen=True)
class TrainConfig:
    """Everything that decides a trained network besides the data: two runs with equal configs (and data) give
    the same weights."""

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    network: NetworkConfig = field(default_factory=lambda: network_config(DEFAULT_ARCH))
    codec: CodecConfig = CodecConfig()
    loss: LossWeights = LossWeights()
    crop: CropPolicy = CropPolicy()
    augmentation: Augmentation = Augmentation()
    #: What the windows vary over beyond the scene's one look (:mod:`vc.model.camera_range`); None: nothing, as
    #: before it existed. A compile turns it on (``train.camera_range``).
    camera_range: CameraRange | None = None
    decode: DecodeConfig = DecodeConfig()
    steps: int = 1800  # ~20 minutes per region of the demo scene on 2 cores (fast preset, 256x256 windows)
    batch_size: int = 16
    learning_rate: float = 2e-3
    weight_decay: float = 1e-4
    warmup_steps: int = 100
    seed: int = 0
    checkpoint_every: int = 200
    held_out_fraction: float = 0.1
    #: Forward pass in bfloat16 (torch.autocast; weights, loss and optimiser stay fp32). On a CPU with bf16
    #: instructions a training step of the fast network takes about half the time (benchmarks/model_speed.py
    #: --compute). Explicit here, so that a run's stored config says what it trained with; a compile's ``auto``
    #: (stages/config.py) turns it on where :func:`native_bf16`.
    bf16_autocast: bool = False
    #: Activations in channels-last (NHWC) memory order, which oneDNN's convolutions prefer on the CPU.
    channels_last: bool = False

    def __post_init__(self) -> None:
        # The output stride is the network's alone: the codec that draws the targets and the decoder that reads
        # the outputs take it from there, so no caller can pass a mismatched one.
        stride = self.network.stem_stride
        object.__setattr__(self, "codec", replace(self.codec, stride=stride))
        object.__setattr__(self, "decode", replace(self.decode, stride=stride))
        # Asked to draw the centre offsets (and the fine centre map), the codec decides the network's maps: it emits
        # (and, supervised, believes) them too.
        drawn = self.codec.channels
        if drawn != HEATMAP_CHANNELS and self.network.heatmap_channels != drawn:
            believed = drawn if self.network.intermediate_supervision else self.network.belief_channels
            object.__setattr__(self, "network", replace(self.network, heatmap_channels=drawn,
                                                        belief_channels=believed))
        elif drawn == HEATMAP_CHANNELS and self.network.heatmap_channels != HEATMAP_CHANNELS:
            raise ValueError(f"the network emits centre offsets (heatmap_channels {self.network.heatmap_channels}) "
                             "that the codec does not draw: set codec.centre_offsets")
        if self.steps < 1 or self.batch_size < 1:
            raise ValueError("steps and batch_size must be at least 1")

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> TrainConfig:
        """The config written by :meth:`to_dict`, nested configs included, validated by pydantic: an unknown field
        anywhere is an error (a newer writer), a field the writer predates takes its default (the rule for a new
        field: its default reproduces what the code did before it); a settled decoder switch at its settled value
        is dropped (:func:`vc.deploy.decode.stored_decode_fields`). Raises pydantic's ValidationError (a
        ValueError), or :class:`~vc.deploy.decode.RetiredSetting` (one too) for a decoding or a network layout
        this version no longer has; :func:`read_train_config` turns either into an InputError naming the field."""
        if isinstance(data, dict):
            data = dict(data)
            for section, stored in (("network", stored_network_fields), ("decode", stored_decode_fields)):
                if section in data:
                    try:
                        data[section] = stored(data[section])
                    except RetiredSetting as error:
                        raise RetiredSetting(f"{section}.{error.field}", error.reason) from None
        return _TRAIN_CONFIG.validate_python(data)


_TRAIN_CONFIG = TypeAdapter(TrainConfig)


def centre_map_settings(sigma: float) -> dict:
    """:class:`TrainConfig` fields for a centre map of Gaussians ``sigma`` person heights wide. Three settings
    move together: the codec draws the Gaussians; the decoder's smallest separation between two people's peaks
    scales with them (two Gaussians closer than about two sigmas merge into one peak); and the detection loss's
    weight grows as their area shrinks, so that the centre term keeps its share of the loss (an MSE over all cells
    is proportional to the Gaussians' area, as :class:`LossWeights` says of the keypoint maps)."""
    default = CodecConfig.centre_sigma
    return {"codec": replace(CodecConfig(), centre_sigma=sigma),
            "decode": replace(DecodeConfig(),
                              min_centre_separation=DecodeConfig.min_centre_separation * sigma / default),
            "loss": replace(LossWeights(), detection=LossWeights.detection * (default / sigma) ** 2)}


def read_train_config(data: dict, path: Path) -> TrainConfig:
    """:meth:`TrainConfig.from_dict` for the config stored in the file at ``path``: one InputError naming the file
    and the first offending field (``train_config.<field>``), every problem in its reason. A decoding or a network
    layout this version no longer has is refused the same way: the region is trained again with this version."""
    try:
        return TrainConfig.from_dict(data)
    except RetiredSetting as error:
        raise InputError(path, f"train_config.{error.field}", f"trained with {error.reason}; train the region "
                                                              f"again with this version") from None
    except ValidationError as error:
        problems = error.errors()
        where = [".".join(str(part) for part in problem["loc"]) for problem in problems]
        reason = "; ".join(f"{field or 'config'}: {problem['msg']}" for field, problem in zip(where, problems,
                                                                                               strict=True))
        raise InputError(path, f"train_config.{where[0]}".rstrip("."), f"stored training config not readable by "
                                                                       f"this version ({reason})") from None


def native_bf16() -> bool:
    """Whether the device :func:`select_device` picks computes in bfloat16 natively: a CUDA GPU that supports it,
    or a CPU with bf16 instructions (:data:`vc.cores.BF16_INSTRUCTIONS`). Elsewhere PyTorch emulates bf16, slower
    than fp32, so a compile's ``auto`` compute stays in fp32 there."""
    if torch.cuda.is_available():
        return torch.cuda.is_bf16_supported()
    return bool(cpu_facts()[1])


#: Most data-loading processes feeding one GPU: on an H200 the data, not the arithmetic, limits training
#: (docs/decisions/0008-compile-time.md).
GPU_DATA_WORKERS = 12


#: Up to this many usable cores, the CPU's windows are cut in the training process itself: a loader process
#: would be a third busy thread on two cores, and the step's threads, which meet at every operator, wait for
#: whichever of them the scheduler parked: in-process, a 2-core training is faster, with the same weights
#: (docs/decisions/0008-compile-time.md).
IN_PROCESS_LOADING_CORES = 2


def data_workers(device: torch.device) -> int:
    """Data-loading processes for training on ``device``. On a CPU of at most
    :data:`IN_PROCESS_LOADING_CORES` cores none (see there); on a larger one one: the step takes the cores, and a
    second loader only competes with it. On a GPU the step takes milliseconds and decoding the PNG windows is the
    limit, so every core but two (the main process and the system), at most :data:`GPU_DATA_WORKERS`."""
    if device.type == "cpu":
        return 0 if usable_cores() <= IN_PROCESS_LOADING_CORES else 1
    return max(1, min(GPU_DATA_WORKERS, usable_cores() - 2))


def select_device() -> torch.device:
    """CUDA when torch sees a GPU; otherwise the CPU with one thread per core this process may use."""
    if torch.cuda.is_available():
        return torch.device("cuda")
    torch.set_num_threads(usable_cores())
    return torch.device("cpu")


def learning_rate_factor(step: int, config: TrainConfig) -> float:
    """Linear warm-up, then a cosine decay to zero at the last step."""
    if step < config.warmup_steps:
        return (step + 1) / config.warmup_steps
    progress = (step - config.warmup_steps) / max(config.steps - config.warmup_steps, 1)
    return 0.5 * (1.0 + math.cos(math.pi * min(progress, 1.0)))


def reference_height_m(data: RegionData) -> float:
    """The median stature of the region's training people: the height the decoder's boxes assume."""
    heights = [a["attributes"]["height_m"] for sample in data.train for a in sample.annotations]
    return float(np.median(heights)) if heights else 1.72


@dataclass
class Checkpoint:
    path: Path
    content: dict

    @cached_property
    def config(self) -> TrainConfig:
        """The training config the checkpoint was written with (an InputError naming the field if this version
        cannot read it)."""
        return read_train_config(self.content.get("train_config"), self.path)

    @property
    def step(self) -> int:
        return int(self.content["step"])

    @property
    def dataset(self) -> Path:
        """The dataset the region was trained on. Stored relative to the run folder (checkpoints written before
        were absolute), so a run moved together with its renders still finds them."""
        return (self.path.parent.parent / self.content["dataset"]).resolve()


def content_digest(content: dict) -> str:
    """SHA-256 of a checkpoint's content: each tensor's dtype, shape and bytes and each other value's repr, dict
    keys in sorted order. ``torch.load`` does not check the archive's CRCs (a flipped bit in a weight loads
    silently), so the digest stored beside the content is what finds a damaged file."""
    digest = hashlib.sha256()

    def feed(value: object) -> None:
        if isinstance(value, torch.Tensor):
            tensor = value.detach().cpu().contiguous()
            digest.update(f"T{tensor.dtype}{tuple(tensor.shape)}:".encode())
            digest.update(tensor.reshape(-1).view(torch.uint8).numpy().tobytes())
        elif isinstance(value, dict):
            digest.update(f"D{len(value)}:".encode())
            for key in sorted(value, key=repr):
                feed(key)
                feed(value[key])
        elif isinstance(value, list | tuple):
            digest.update(f"L{len(value)}:".encode())
            for item in value:
                feed(item)
        else:
            text = repr(value).encode()
            digest.update(f"V{len(text)}:".encode() + text)

    feed(content)
    return digest.hexdigest()


def checkpoint_path(run: Path, region: str) -> Path:
    return run / "checkpoints" / f"{region}.pt"


def load_checkpoint(path: Path, scene_hash: str | None = None, region: str | None = None) -> Checkpoint:
    """Read a checkpoint and check that it belongs to ``scene_hash`` and ``region`` (when given).

    Only tensors and plain data (dicts, lists, strings, numbers) are read (``weights_only``): unpickling anything
    else could run code a hostile file brings, and a checkpoint this version writes holds nothing else."""
    try:
        # TorchVersion (a str) is the one object checkpoints written before this rule hold: allowed by name.
        with torch.serialization.safe_globals([TorchVersion]):
            content = torch.load(path, map_location="cpu", weights_only=True)
    except FileNotFoundError:
        raise InputError(path, "", "checkpoint not found") from None
    except pickle.UnpicklingError as error:
        found = str(error).split("Unsupported global: GLOBAL ", 1)[-1].split(" ", 1)[0] if "GLOBAL" in str(error) \
            else "an object"
        raise InputError(path, "", f"refused: it holds a Python object ({found}) beyond tensors and plain data, "
                                   f"and loading it could run code") from None
    except Exception as error:  # torch raises many types for a damaged file
        raise InputError(path, "", f"not a readable checkpoint ({type(error).__name__}: {error})") from None
    if not isinstance(content, dict) or content.get("kind") != CHECKPOINT_KIND:
        raise InputError(path, "kind", f"not a {CHECKPOINT_KIND}")
    if content.get("format_version") not in READABLE_CHECKPOINT_FORMATS:
        raise InputError(path, "format_version", f"unsupported checkpoint format {content.get('format_version')!r} "
                                                 f"(this version reads "
                                                 f"{', '.join(map(str, READABLE_CHECKPOINT_FORMATS))})")
    if content["format_version"] >= 2 and content.pop("content_sha256", None) != content_digest(content):
        raise InputError(path, "content_sha256", "the checkpoint does not match its digest (the file is damaged); "
                                                 "restore it, or delete it to train this region from the start")
    if scene_hash is not None and content["scene_hash"] != scene_hash:
        raise InputError(path, "scene_hash", f"checkpoint belongs to scene {content['scene']!r} "
                                             f"({content['scene_hash'][:12]}…), not to this dataset's scene "
                                             f"({scene_hash[:12]}…); train into a new run folder")
    if region is not None and content["region"] != region:
        raise InputError(path, "region", f"checkpoint is for region {content['region']!r}, not {region!r}")
    checkpoint = Checkpoint(path, content)
    checkpoint.config  # noqa: B018 (read now: a config this version cannot read is an error at load, not later)
    return checkpoint


def _differences(old: dict, new: dict, prefix: str = "") -> list[str]:
    changes = []
    for key in sorted(set(old) | set(new)):
        a, b = old.get(key), new.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            changes += _differences(a, b, f"{prefix}{key}.")
        elif a != b and not (isinstance(a, list | tuple) and isinstance(b, list | tuple) and list(a) == list(b)):
            changes.append(f"{prefix}{key} {a!r} -> {b!r}")
    return changes


@dataclass
class RegionResult:
    region: str
    evaluation: RegionEvaluation
    steps: int
    train_seconds: float
    images_per_second: float
    final_loss: float
    parameters: int
    receptive_field: int
    reference_height_m: float

    def to_dict(self) -> dict:
        return {**self.evaluation.evaluation.to_dict(), "steps": self.steps,
                "train_seconds": round(self.train_seconds, 1),
                "train_images_per_second": round(self.images_per_second, 2), "final_loss": self.final_loss,
                "parameters": self.parameters, "receptive_field_px": self.receptive_field,
                "reference_height_m": round(self.reference_height_m, 4)}


def memory_format(config: TrainConfig) -> torch.memory_format:
    return torch.channels_last if config.channels_last else torch.contiguous_format


def forward(net: torch.nn.Module, images: torch.Tensor, config: TrainConfig) -> dict:
    """The network's training outputs in fp32, computed in bfloat16 when the config asks (``bf16_autocast``)."""
    with torch.autocast(images.device.type, dtype=torch.bfloat16, enabled=config.bf16_autocast):
        outputs = net(images)
    if not config.bf16_autocast:
        return outputs
    return {"heatmaps": outputs["heatmaps"].float(), "beliefs": [belief.float() for belief in outputs["beliefs"]]}


class RegionTrainer:
    """Trains, checkpoints and evaluates one region's network in ``run``."""

    def __init__(self, data: RegionData, config: TrainConfig, run: Path, dataset: Path,
                 device: torch.device | None = None, workers: int = 1, show_progress: bool = True) -> None:
        self.data, self.config, self.run, self.dataset = data, config, run, dataset
        self.device = device or select_device()
        self.workers, self.show_progress = workers, show_progress
        self.path = checkpoint_path(run, data.name)
        torch.manual_seed(config.seed)
        self.net = ScenePoseNet(config.network).to(self.device, memory_format=memory_format(config))
        self.optimizer = torch.optim.AdamW(self.net.parameters(), lr=config.learning_rate,
                                           weight_decay=config.weight_decay)
        self.schedule = torch.optim.lr_scheduler.LambdaLR(self.optimizer,
                                                          lambda step: learning_rate_factor(step, config))
        self.step, self.history, self.train_seconds = 0, {"step": [], "loss": []}, 0.0
        self.reference_height_m = reference_height_m(data)
        if self.path.exists():
            self._resume(load_checkpoint(self.path, data.manifest["scene_hash"], data.name))

    def _resume(self, checkpoint: Checkpoint) -> None:
        # The decoder only scores held-out renders: a run resumes under another decoder's settings.
        changes = [change for change in _differences(checkpoint.config.to_dict(), self.config.to_dict())
                   if not change.startswith("decode.")]
        if changes:
            raise InputError(checkpoint.path, "train_config", "this run was started with other settings ("
                             + "; ".join(changes) + "); resume with the same options or use a new run folder")
        self.net.load_state_dict(checkpoint.content["model"])
        self.optimizer.load_state_dict(checkpoint.content["optimizer"])
        self.schedule.load_state_dict(checkpoint.content["schedule"])
        self.step, self.history = checkpoint.step, checkpoint.content["history"]
        self.train_seconds = checkpoint.content["train_seconds"]

    def _save(self) -> None:
        content = {
            "kind": CHECKPOINT_KIND, "format_version": CHECKPOINT_FORMAT,
            "scene": self.data.manifest["scene"], "scene_hash": self.data.manifest["scene_hash"],
            "region": self.data.name, "region_entry": self.data.region,
            "dataset": os.path.relpath(Path(self.dataset).resolve(), Path(self.run).resolve()),
            "scene_camera": self.data.manifest.get("camera"),
            "dataset_settings": self.data.manifest["settings"], "train_config": self.config.to_dict(),
            "reference_height_m": self.reference_height_m, "step": self.step, "history": self.history,
            "train_seconds": self.train_seconds, "versions": {"torch": str(torch.__version__)},
            "model": self.net.state_dict(), "optimizer": self.optimizer.state_dict(),
            "schedule": self.schedule.state_dict(),
        }
        content["content_sha256"] = content_digest(content)
        # Serialised in memory and written by Python, so that a full disk is an OSError naming the file (torch's
        # own writer fails with a bare RuntimeError) and the previous checkpoint stays in place.
        buffer = io.BytesIO()
        torch.save(content, buffer)
        with atomic_path(self.path) as temporary:
            temporary.write_bytes(buffer.getbuffer())

    def _loader(self, last: int) -> DataLoader:
        life = None if self.config.camera_range is None else camera_life_of(self.data.manifest, self.data.region,
                                                                             self.config.camera_range, self.config.seed)
        stream = TrainingStream(self.data.train, self.config.codec, self.data.input_size, self.config.crop,
                                self.config.augmentation, self.config.seed, camera_life=life)
        batch = self.config.batch_size
        draws = range(self.step * batch, last * batch)
        return DataLoader(stream, batch_size=batch, sampler=draws, num_workers=self.workers,
                          persistent_workers=False, prefetch_factor=4 if self.workers else None)

    def train(self, until: int | None = None) -> None:
        """Run the remaining steps (or up to step ``until``), checkpointing every ``checkpoint_every`` steps and
        at the end."""
        last = self.config.steps if until is None else min(until, self.config.steps)
        if self.step >= last:
            return
        self.net.train()
        window: list[float] = []
        started, first_step = time.perf_counter(), self.step
        with tqdm(total=self.config.steps, initial=self.step, desc=f"train {self.data.name}", unit="step",
                  disable=not self.show_progress, dynamic_ncols=True) as bar:
            for images, targets in self._loader(last):
                images = images.to(self.device, memory_format=memory_format(self.config))
                loss, _ = scene_pose_loss(forward(self.net, images, self.config), targets.to(self.device),
                                          self.config.loss)
                if not torch.isfinite(loss):
                    saved = (f"the last good checkpoint ({self.path}, step {load_checkpoint(self.path).step}) is "
                             f"kept" if self.path.is_file() else "no checkpoint was written yet")
                    raise StageError(f"{self.data.name}: the training loss became {loss.item()} at step {self.step} "
                                     f"and training stopped; {saved}. Nothing non-finite was saved: resume with a "
                                     "lower learning rate, or check the renders")
                self.optimizer.zero_grad(set_to_none=True)
                loss.backward()
                self.optimizer.step()
                self.schedule.step()
                self.step += 1
                value = loss.item()
                window.append(value)
                checkpoint_due = self.step % self.config.checkpoint_every == 0 or self.step == last
                if self.step % HISTORY_EVERY == 0 or checkpoint_due:  # a checkpoint never loses a partial window
                    self.history["step"].append(self.step)
                    self.history["loss"].append(float(np.mean(window)))
                    window = []
                elapsed = time.perf_counter() - started
                rate = (self.step - first_step) * self.config.batch_size / elapsed
                bar.set_postfix(loss=f"{value:.2e}", img_s=f"{rate:.1f}", refresh=False)
                bar.update(1)
                if checkpoint_due:
                    self.train_seconds += time.perf_counter() - started
                    started, first_step = time.perf_counter(), self.step
                    self._save()

    def evaluate(self) -> RegionResult:
        """Held-out accuracy, and the precision-recall and loss curves under ``run/<region>/``."""
        camera = camera_from_dict(self.data.region["camera"])
        heights = expected_height_map(camera, self.config.codec.stride, self.reference_height_m)
        evaluation = evaluate_network(self.net, self.data.held_out, self.config.decode,
                                      heights, self.device, self.show_progress, f"evaluate {self.data.name}")
        folder = self.run / self.data.name
        plot_precision_recall({"held-out synthetic": evaluation.evaluation}, folder / "precision_recall.png",
                              f"{self.data.manifest['scene']} {self.data.name}: {len(self.data.held_out)} held-out "
                              f"samples")
        if self.history["step"]:
            plot_training_curve(self.history["step"], self.history["loss"], folder / "training_loss.png",
                                f"{self.data.manifest['scene']} {self.data.name} ({self.config.network.name})")
        return RegionResult(
            region=self.data.name, evaluation=evaluation, steps=self.step, train_seconds=self.train_seconds,
            images_per_second=self.step * self.config.batch_size / max(self.train_seconds, 1e-9),
            final_loss=round(self.history["loss"][-1], 6) if self.history["loss"] else float("nan"),
            parameters=sum(p.numel() for p in self.net.parameters()),
            receptive_field=self.net.receptive_field(), reference_height_m=self.reference_height_m)
