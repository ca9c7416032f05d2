"""Typed, JSON-serialisable ScenePoseNet configurations and the named presets (docs/design.md, "Model: ScenePoseNet").

A checkpoint and an exported bundle must be able to rebuild the exact network they were trained with, so the
architecture is a frozen value written next to the weights (``to_dict``) and read back by pydantic
(``from_dict``): an unknown field is an error (a newer writer) instead of a silently different network, and a
field the writer predates takes the value that reproduces the network it wrote: the field's default, by the rule
every new field follows. The one exception is ``heatmap_channels``: a config without it describes a network of the
retired 19-map layout, which is refused (:func:`stored_network_fields`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Literal

from pydantic import TypeAdapter

# The output heat maps' layout (centre, 17 COCO keypoints, mask, handedness) is the decoder's: one definition,
# in deploy.
from vc.deploy.decode import RetiredSetting
from vc.deploy.heatmaps import ANATOMICAL_CHANNELS, HEATMAP_CHANNELS, LAYOUTS

__all__ = ["DEFAULT_ARCH", "HEATMAP_CHANNELS", "PRESETS", "STEMS", "STEM_STRIDES", "NetworkConfig",
           "network_config"]

STEM_STRIDES = (1, 2, 4)
#: How the stem downsamples: "conv", the paper's 5x5 (strided, and a strided 3x3 after it for stride 4); "patch",
#: one convolution with kernel = stride over non-overlapping patches (the "patchify" stem of ConvNeXt, Liu et al.,
#: 2022). On a CPU the 5x5 over three input channels at half resolution is the slowest layer per multiply-add
#: (im2col over a thin, wide tensor); patches read every input pixel once, at the output resolution.
STEMS = ("conv", "patch")


@dataclass(frozen=True)
class NetworkConfig:
    """The architecture of one ScenePoseNet; ``name`` only says which preset it came from.

    The paper runs every layer at full resolution with dense 17x17 kernels; the other presets trade that for CPU
    speed with a strided stem (heat maps come out at 1/``stem_stride`` of the input) and cheaper large kernels,
    while keeping the receptive field larger than the biggest person a region shows.
    """

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    name: str
    stem_stride: int  # 1, 2 or 4; the output stride of the heat maps
    width: int  # feature channels throughout the trunk
    sb_depthwise: bool  # SB large kernels as depthwise k x k + pointwise 1x1 instead of dense k x k
    intermediate_supervision: bool  # return every SB unit's belief maps so the loss can supervise them too
    residual_units: int = 4  # 3x3 residual units after the stem
    sb_units: int = 3  # spatial-belief units (the paper's ablations use 1 to 3)
    sb_kernel: int = 17  # odd side of the SB residual path's large kernels
    sb_reduction: int = 1  # 1: two full-width k x k convolutions (the paper); r > 1: a 1x1 -> k x k -> 1x1
    # bottleneck whose one k x k runs at width/r channels (He et al., 2016), about 2r^2 times cheaper
    sb_separable: bool = False  # SB large kernels as a dense k x 1 then 1 x k (same window, 2/k of the cost)
    belief_channels: int = HEATMAP_CHANNELS  # belief maps each SB unit emits through its 1x1 path
    heatmap_channels: int = HEATMAP_CHANNELS  # output maps, one of LAYOUTS
    stem: Literal["conv", "patch"] = "conv"  # see STEMS

    def __post_init__(self) -> None:
        problems = []
        if self.stem_stride not in STEM_STRIDES:
            problems.append(f"stem_stride must be one of {STEM_STRIDES}, got {self.stem_stride}")
        if self.width < 1 or self.belief_channels < 1 or self.sb_units < 1 or self.residual_units < 0:
            problems.append("width, belief_channels and sb_units must be >= 1 and residual_units >= 0")
        if self.sb_reduction < 1 or self.width % self.sb_reduction:
            problems.append(f"sb_reduction must be >= 1 and divide width {self.width}, got {self.sb_reduction}")
        if self.sb_kernel < 1 or self.sb_kernel % 2 == 0:
            problems.append(f"sb_kernel must be odd so that 'same' padding keeps maps aligned, got {self.sb_kernel}")
        if self.stem not in STEMS:
            problems.append(f"stem must be one of {STEMS}, got {self.stem!r}")
        elif self.stem == "patch" and self.stem_stride == 1:
            problems.append("a patch stem needs stem_stride 2 or 4 (patches of 1 pixel would be a 1x1 convolution)")
        if self.sb_separable and self.sb_depthwise:
            problems.append("sb_separable and sb_depthwise are two ways to factor the same kernel: choose one")
        if self.heatmap_channels not in LAYOUTS:
            problems.append(f"heatmap_channels must be one of the layouts {LAYOUTS} (vc.deploy.heatmaps), got "
                            f"{self.heatmap_channels}")
        if self.intermediate_supervision and self.belief_channels != self.heatmap_channels:
            problems.append(f"intermediate supervision compares beliefs with the {self.heatmap_channels} target heat "
                            f"maps, so belief_channels must be {self.heatmap_channels}, got {self.belief_channels}")
        if problems:
            raise ValueError(f"invalid network config {self.name!r}: " + "; ".join(problems))

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> NetworkConfig:
        """The config written by :meth:`to_dict` (see the module docstring); raises pydantic's ValidationError (a
        ValueError) naming the offending fields, or :class:`~vc.deploy.decode.RetiredSetting` (one too) for a
        network of the retired layout."""
        return _NETWORK_CONFIG.validate_python(stored_network_fields(data))


def stored_network_fields(data: dict) -> dict:
    """A stored network config as this version reads it. One without ``heatmap_channels`` (written before the
    field) or with :data:`~vc.deploy.heatmaps.ANATOMICAL_CHANNELS` describes a network of the retired 19-map layout,
    which nothing here trains, exports or decodes: :class:`~vc.deploy.decode.RetiredSetting`."""
    if isinstance(data, dict) and data.get("heatmap_channels", ANATOMICAL_CHANNELS) == ANATOMICAL_CHANNELS:
        raise RetiredSetting("heatmap_channels", f"a network of {ANATOMICAL_CHANNELS} heat maps (the layout from "
                                                 "before the handedness maps), which this version does not decode "
                                                 "(docs/decisions/0003-decoder-settings.md)")
    return data


_NETWORK_CONFIG = TypeAdapter(NetworkConfig)


PRESETS: dict[str, NetworkConfig] = {
    # The paper: everything at full resolution, dense 17x17 kernels (about 30 M parameters).
    "paper": NetworkConfig("paper", stem_stride=1, width=128, sb_depthwise=False, intermediate_supervision=True),
    # The CPU network before "fast-sep" (benchmarks/model_speed.py): 1/4 resolution, 32 channels, two 3x3 residual
    # units, SB units as bottlenecks around one dense 13x13 at 16 channels (receptive field 185 px); ~10x faster to
    # train than "dense9" at the same input.
    "fast": NetworkConfig("fast", stem_stride=4, width=32, residual_units=2, sb_kernel=13, sb_reduction=2,
                          sb_depthwise=False, intermediate_supervision=True),
    # The default: "fast" with each 13x13 as a 13x1 then a 1x13 (same receptive field, 2/13 of those multiply-adds):
    # real AP50 held on PETS09, training and the int8 network faster (docs/decisions/0004-network-architecture.md).
    "fast-sep": NetworkConfig("fast-sep", stem_stride=4, width=32, residual_units=2, sb_kernel=13, sb_reduction=2,
                              sb_depthwise=False, sb_separable=True, intermediate_supervision=True),
    # "fast-sep" with a patch stem (STEMS): a 4x4, stride 4 convolution in place of the 5x5 at half resolution and
    # the strided 3x3 after it: faster, but lower real AP50 in every seed, so a faster point and not the default
    # (docs/decisions/0004-network-architecture.md).
    "fast-patch": NetworkConfig("fast-patch", stem_stride=4, width=32, residual_units=2, sb_kernel=13,
                                sb_reduction=2, sb_depthwise=False, sb_separable=True, intermediate_supervision=True,
                                stem="patch"),
    # The paper's two dense convolutions per SB unit, 9x9 at 1/4 resolution, 64 channels (receptive field 265 px).
    "dense9": NetworkConfig("dense9", stem_stride=4, width=64, sb_kernel=9, sb_depthwise=False,
                            intermediate_supervision=True),
    # The paper's 17x17 kernels at 1/4 resolution, made cheap by depthwise separation (receptive field 425 px).
    "fast-dw": NetworkConfig("fast-dw", stem_stride=4, width=32, residual_units=2, sb_depthwise=True,
                             intermediate_supervision=True),
}
DEFAULT_ARCH = "fast-sep"


def network_config(name: str) -> NetworkConfig:
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown network preset {name!r}; choose one of {', '.join(PRESETS)}") from None
