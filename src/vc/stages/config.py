"""One typed config of a compile, and the budgets as its presets.

A compile is four stages' settings (render, train, export, self-test); each field's default is the one its
library states (``SynthesisSettings``, ``DEFAULT_SHARD_SIZE``, ``TrainConfig``, ``bundle_files``), so there is
one source for every default, and a budget (:data:`PRESETS`) is the config with a few fields changed, as
nerfstudio's method configs are presets of one config tree. pydantic, not dataclasses: a config file is user
input, and its validation names the field and the reason (``train.steps: Input should be greater than 0``).

Every compile writes its full config (``OUT/compile_config.yaml``); ``vc-compile --config FILE`` reads one back
and ``--set section.field=value`` changes single fields.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator

from vc.errors import InputError
from vc.io import atomic_path
from vc.model.camera_range import CameraRange
from vc.model.codec import CodecConfig
from vc.model.config import DEFAULT_ARCH, network_config
from vc.model.config import PRESETS as NETWORK_PRESETS
from vc.model.loss import LossWeights
from vc.model.trainer import TrainConfig, centre_map_settings, native_bf16
from vc.render.dataset import MIN_SHARDS
from vc.render.job import DEFAULT_SHARD_SIZE
from vc.render.synthesis import SynthesisSettings

CONFIG_FILE = "compile_config.yaml"
DEFAULT_PRESET = "standard"


class _Section(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


class RenderSettings(_Section):
    """How many samples each region gets and how each is made (``vc-render``)."""

    samples: int = Field(ge=1, description="rendered samples per region")
    spp: int = Field(SynthesisSettings.spp, ge=1, description="path-tracing samples per pixel")
    seed: int = Field(SynthesisSettings.seed, ge=0, description="dataset seed")
    max_people: int | None = Field(SynthesisSettings.max_people, ge=0,
                                   description="most people per sample (None: from the region's ground area)")
    shard_size: int = Field(DEFAULT_SHARD_SIZE, ge=1, description="samples per shard (the unit of resuming)")

    def synthesis(self) -> SynthesisSettings:
        return SynthesisSettings(spp=self.spp, seed=self.seed, max_people=self.max_people)


class TrainSettings(_Section):
    """The network and its optimisation (``vc-train``); the rest of :class:`TrainConfig` keeps its defaults."""

    arch: Literal[tuple(sorted(NETWORK_PRESETS))] = DEFAULT_ARCH  # type: ignore[valid-type]
    width: int | None = Field(None, ge=1, description="the preset's channel width, overridden")
    sb_units: int | None = Field(None, ge=1, description="the preset's number of SB units, overridden")
    steps: int = Field(TrainConfig.steps, ge=1, description="optimiser steps per region")
    batch_size: int = Field(TrainConfig.batch_size, ge=1, description="windows per step")
    seed: int = Field(TrainConfig.seed, description="seed of the weights and the data order")
    workers: Annotated[int, Field(ge=0)] | Literal["auto"] = Field(
        "auto", description="data-loading processes (not part of what is trained); auto: on the CPU none "
                            "(in the training process) up to 2 cores and 1 above, on a GPU every core but two, "
                            "at most 12")
    bf16_autocast: bool | Literal["auto"] = Field("auto", description="forward pass in bfloat16; auto: where "
                                                  "the hardware has bf16 instructions (about twice as fast there)")
    channels_last: bool | Literal["auto"] = Field("auto", description="NHWC activations (oneDNN's preferred order "
                                                  "on the CPU); auto: with bf16")
    centre_sigma: float | None = Field(None, gt=0.0, le=0.5,
                                       description="the centre map's Gaussian, in person heights (None: the codec's); "
                                                   "sharper lets people one behind another keep two peaks")
    centre_offsets: bool = Field(False, description="also learn, at each person pixel, where that person's centre "
                                                    "is: the decoder splits people in one blob by their pixels' votes "
                                                    "(on in the standard and full budgets)")
    fine_centre: bool = Field(False, description="also learn the centre map at twice the resolution (with "
                                                 "centre_offsets): people one behind another, 1.5-2 heat-map cells "
                                                 "apart, are learned as two (on in the standard and full "
                                                 "budgets)")
    head_map: bool = Field(False, description="also learn a map of people's heads and one of their heights (with "
                                              "fine_centre): people in a group whose centres blur into one "
                                              "peak are read again from their heads")
    camera_range: CameraRange | None = Field(CameraRange(), description="what every window varies over besides the "
                                             "scene's one look: exposure, white balance, night IR, gain noise, "
                                             "blur, compression (vc.model.camera_range; null: nothing)")
    facing: bool = Field(True, description="also train the facing model, which reads from each person's crop "
                                           "whether they are seen from the front or from behind "
                                           "(vc.model.facing; a dataset with too few people skips it)")
    crop_pose: bool | Literal["auto"] = Field("auto", description="also train the keypoint model, which reads the "
                                                "keypoints of people 100 px and taller again from their own crop "
                                                "(vc.model.crop_pose); auto: where most of the scene's people are "
                                                "that tall (docs/decisions/0040-keypoint-model-by-size.md)")
    centre_offset_weight: float = Field(LossWeights.centre_offsets, gt=0.0,
                                        description="the centre offsets' share of the loss (with centre_offsets): "
                                                    "lower leaves more of the network to the keypoint maps")

    @field_validator("width", "sb_units")
    @classmethod
    def _network_takes_it(cls, value: int | None, info: ValidationInfo) -> int | None:
        """Checked when the config is read, not when training starts after the renders."""
        if value is None:
            return value
        overrides = {"width": info.data.get("width"), info.field_name: value}
        replace(network_config(info.data.get("arch", DEFAULT_ARCH)),
                **{name: given for name, given in overrides.items() if given is not None})  # ValueError: refused
        return value

    @field_validator("centre_offset_weight")
    @classmethod
    def _weight_needs_offsets(cls, weight: float, info: ValidationInfo) -> float:
        if weight != LossWeights.centre_offsets and not info.data.get("centre_offsets", False):
            raise ValueError("weighs the centre offsets, which this training does not learn (set centre_offsets)")
        return weight

    @field_validator("fine_centre")
    @classmethod
    def _fine_centre_needs_offsets(cls, fine: bool, info: ValidationInfo) -> bool:
        if fine and not info.data.get("centre_offsets", False):
            raise ValueError("the fine centre map comes with the centre offsets (set centre_offsets)")
        return fine

    @field_validator("head_map")
    @classmethod
    def _head_map_needs_fine_centre(cls, head: bool, info: ValidationInfo) -> bool:
        if head and not info.data.get("fine_centre", False):
            raise ValueError("the head map comes with the fine centre map (set fine_centre)")
        return head

    def train_config(self) -> TrainConfig:
        """The full training config (a width or SB count the network cannot take was refused when read)."""
        overrides = {key: value for key, value in (("width", self.width), ("sb_units", self.sb_units))
                     if value is not None}
        network = replace(network_config(self.arch), **overrides)
        bf16 = native_bf16() if self.bf16_autocast == "auto" else self.bf16_autocast
        channels_last = bf16 if self.channels_last == "auto" else self.channels_last
        centre = {} if self.centre_sigma is None else centre_map_settings(self.centre_sigma)
        if self.centre_offsets:
            centre["codec"] = replace(centre.get("codec", CodecConfig()), centre_offsets=True,
                                      fine_centre=self.fine_centre, head_map=self.head_map)
            centre["loss"] = replace(centre.get("loss", LossWeights()), centre_offsets=self.centre_offset_weight)
        return TrainConfig(network=network, steps=self.steps, batch_size=self.batch_size, seed=self.seed,
                           bf16_autocast=bf16, channels_last=channels_last, camera_range=self.camera_range,
                           **centre)


class ExportSettings(_Section):
    """The bundle's precision and what it is measured on (``vc-export``)."""

    precision: Literal["fp32", "fp16", "int8", "auto"] = "fp32"
    eval_samples: int = Field(200, ge=0, description="held-out renders per region each precision is measured on")
    calibration_samples: int = Field(64, ge=1, description="training renders per region that calibrate int8")

    @field_validator("eval_samples")
    @classmethod
    def _auto_needs_samples(cls, samples: int, info: ValidationInfo) -> int:
        if samples == 0 and info.data.get("precision") == "auto":
            raise ValueError("precision auto chooses by measuring each precision on held-out renders: give at least "
                             "1, or name the precision (fp32, fp16 or int8)")
        return samples


class SelfTestSettings(_Section):
    """The bundle on full frames composed of held-out renders on the background."""

    frames: int = Field(50, ge=1)


class CompileConfig(_Section):
    """Everything a compile depends on besides the scene."""

    render: RenderSettings
    train: TrainSettings = TrainSettings()
    export: ExportSettings = ExportSettings(precision="auto")
    self_test: SelfTestSettings = SelfTestSettings()

    @field_validator("render")
    @classmethod
    def _renders_two_shards(cls, render: RenderSettings) -> RenderSettings:
        """Training holds whole shards out for evaluation: one shard a region would fail there, after rendering."""
        if -(-render.samples // render.shard_size) < MIN_SHARDS:
            raise ValueError(f"samples {render.samples} in shards of {render.shard_size} make one shard a region, and "
                             f"training holds whole shards out to measure on ({MIN_SHARDS} at least): give more "
                             "samples than shard_size, or a smaller shard_size")
        return render

    def with_seed(self, seed: int) -> CompileConfig:
        """The renders' and the training's seed set together (``vc-compile --seed``)."""
        return self.model_copy(update={"render": self.render.model_copy(update={"seed": seed}),
                                       "train": self.train.model_copy(update={"seed": seed})})

    def to_dict(self) -> dict:
        return self.model_dump(mode="json")


#: The trainer's compute settings by name: ``python -m benchmarks.model_speed --compute`` times them, the accuracy
#: sweep's ``compute`` knob measures what they do to accuracy. A compile's default (``auto``) is bf16 channels-last
#: where the hardware has bf16 instructions, fp32 elsewhere: faster training at the same real accuracy
#: (docs/decisions/0006-training-compute.md).
TRAINING_COMPUTE: dict[str, dict[str, bool]] = {
    "fp32": {"channels_last": False, "bf16_autocast": False},
    "fp32 channels-last": {"channels_last": True, "bf16_autocast": False},
    "bf16": {"channels_last": False, "bf16_autocast": True},
    "bf16 channels-last": {"channels_last": True, "bf16_autocast": True},
}

PRESETS: dict[str, CompileConfig] = {
    # about 10 minutes for the demo scene on 2 cores: a working bundle, not an accurate one. The "fast" network,
    # because "fast-sep" learns less in 200 steps (docs/decisions/0004-network-architecture.md)
    "quick": CompileConfig(render=RenderSettings(samples=300), train=TrainSettings(arch="fast", steps=200),
                           export=ExportSettings(precision="auto", eval_samples=100),
                           self_test=SelfTestSettings(frames=8)),
    # the default: PETS09 in about 26 minutes on 2 cores. Centre offsets and the fine centre map keep people side by
    # side apart (docs/decisions/0003-decoder-settings.md, docs/decisions/0010-fine-centre-map.md), the head map
    # people in groups (docs/decisions/0058-a-head-map-in-every-region.md); none is measured at the quick budget's
    # 200 steps
    "standard": CompileConfig(render=RenderSettings(samples=2000),
                              train=TrainSettings(centre_offsets=True, fine_centre=True, head_map=True)),
    "full": CompileConfig(render=RenderSettings(samples=6000, spp=32),
                          train=TrainSettings(steps=5000, centre_offsets=True, fine_centre=True, head_map=True),
                          self_test=SelfTestSettings(frames=100)),
}


def _validated(data: object, path: Path | None, field_prefix: str = "",
               model: type[BaseModel] = CompileConfig) -> BaseModel:
    try:
        return model.model_validate(data)
    except ValidationError as error:
        problem = error.errors()[0]
        where = ".".join(str(part) for part in problem["loc"]) or "(top level)"
        raise InputError(path, field_prefix + where, problem["msg"].removeprefix("Value error, ")) from None


def train_settings(**fields: object) -> TrainSettings:
    """:class:`TrainSettings` from a command line's options; a bad value raises :class:`InputError` naming its
    field (``train.<field>``)."""
    return _validated(fields, None, "train.", TrainSettings)


def export_settings(**fields: object) -> ExportSettings:
    """:class:`ExportSettings` from a command line's options; a bad value raises :class:`InputError` naming its
    field (``export.<field>``)."""
    return _validated(fields, None, "export.", ExportSettings)


def read_config(path: Path) -> CompileConfig:
    """A compile config file (YAML, as :func:`write_config` writes it); bad input raises :class:`InputError`."""
    try:
        data = yaml.safe_load(Path(path).read_text())
    except OSError as error:
        raise InputError(path, "", f"cannot read the config ({error.strerror})") from None
    except yaml.YAMLError as error:
        raise InputError(path, "", f"not valid YAML ({error})") from None
    return _validated(data, path)


def write_config(config: CompileConfig, path: Path) -> None:
    with atomic_path(path) as temporary:
        temporary.write_text(yaml.safe_dump(config.to_dict(), sort_keys=False))


def with_overrides(config: CompileConfig, assignments: list[str]) -> CompileConfig:
    """``config`` with ``section.field=value`` assignments applied (values read as YAML: ``4``, ``null``,
    ``int8``), validated as a whole."""
    data = config.to_dict()
    for assignment in assignments:
        name, separator, text = assignment.partition("=")
        section, dot, field = name.strip().partition(".")
        if not separator or not dot or section not in data or field not in data[section]:
            raise InputError(None, f"--set {assignment}", "expected section.field=value with a field of "
                                                          f"{', '.join(f'{s}.*' for s in data)}")
        try:
            data[section][field] = yaml.safe_load(text)
        except yaml.YAMLError as error:
            raise InputError(None, f"--set {assignment}", f"the value is not valid YAML ({error})") from None
    return _validated(data, None, "--set ")
