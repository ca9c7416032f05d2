"""ScenePoseNet: the fully convolutional detector, pose estimator and segmenter of the paper (docs/design.md, "Model").

A 5x5 stem convolution (strided in the CPU presets; or one convolution over non-overlapping patches), 3x3 residual
units, then spatial-belief (SB) units: each refines the features with a residual path of large-kernel convolutions,
so that one pixel sees a whole person, and emits belief maps through a 1x1 path; the next unit sees those beliefs
next to the features. The belief maps of all SB units are concatenated (skip connections) and two 1x1 convolutions
turn them into the heat maps.

Only convolutions, batch norm, ReLU, addition and concatenation: every op exports to ONNX (opset 17) and runs
deterministically on the CPU.
"""

from __future__ import annotations

import torch
from torch import Tensor, nn

from vc.model.config import NetworkConfig

#: The image in [0, 1] is centred to [-1, 1] inside the network, so an exported graph needs only uint8 -> /255 in
#: front. The exact statistics hardly matter (batch norm follows the stem); centring keeps the stem well conditioned.
INPUT_CENTRE, INPUT_HALF_RANGE = 0.5, 0.5
#: Initial weight scale of the layers that emit heat maps: they start near 0, the value of almost every target pixel.
OUTPUT_INIT_STD = 1e-3


def _spatial_conv(in_channels: int, out_channels: int, kernel: int, depthwise: bool, stride: int = 1,
                  separable: bool = False) -> nn.Module:
    """A k x k convolution with 'same' padding. ``depthwise``: depthwise-separable (Xception-style, no activation
    between the depthwise and pointwise parts). ``separable``: a dense k x 1 then a dense 1 x k (Szegedy et al.,
    2016, "Rethinking the Inception architecture"), no activation between: the same k x k window for 2/k of the
    multiply-adds, where ORT's int8 kernels are fast (dense convolutions) and its depthwise ones are not."""
    padding = kernel // 2
    if separable:
        return nn.Sequential(nn.Conv2d(in_channels, out_channels, (kernel, 1), (stride, 1), (padding, 0), bias=False),
                             nn.Conv2d(out_channels, out_channels, (1, kernel), (1, stride), (0, padding), bias=False))
    if not depthwise:
        return nn.Conv2d(in_channels, out_channels, kernel, stride, padding, bias=False)
    return nn.Sequential(nn.Conv2d(in_channels, in_channels, kernel, stride, padding, groups=in_channels, bias=False),
                         nn.Conv2d(in_channels, out_channels, 1, bias=False))


def _conv_bn_relu(in_channels: int, out_channels: int, kernel: int, stride: int = 1) -> nn.Sequential:
    return nn.Sequential(_spatial_conv(in_channels, out_channels, kernel, False, stride),
                         nn.BatchNorm2d(out_channels), nn.ReLU(inplace=True))


class _SideInputResidual(nn.Module):
    """``relu(features + branch([features, side]))``: ``side`` holds extra maps (the previous SB unit's beliefs)
    that the branch reads next to the features; the skip carries the features alone, so the unit keeps its
    channel count without a projection."""

    branch: nn.Sequential

    def __init__(self) -> None:
        super().__init__()
        self.relu = nn.ReLU(inplace=True)

    def forward(self, features: Tensor, side: Tensor | None = None) -> Tensor:
        branch_input = features if side is None else torch.cat([features, side], dim=1)
        return self.relu(features + self.branch(branch_input))


class ResidualUnit(_SideInputResidual):
    """Two k x k conv-BN layers added to an identity skip (He et al., 2016)."""

    def __init__(self, channels: int, kernel: int, depthwise: bool = False, side_channels: int = 0,
                 separable: bool = False) -> None:
        super().__init__()
        self.branch = nn.Sequential(
            _spatial_conv(channels + side_channels, channels, kernel, depthwise, separable=separable),
            nn.BatchNorm2d(channels), nn.ReLU(inplace=True),
            _spatial_conv(channels, channels, kernel, depthwise, separable=separable), nn.BatchNorm2d(channels))


class BottleneckUnit(_SideInputResidual):
    """A residual unit whose branch is 1x1 (to ``channels / reduction``) -> k x k -> 1x1 (back), each followed by
    batch norm (He et al., 2016): the large kernel sees the same window at a fraction of the dense cost."""

    def __init__(self, channels: int, kernel: int, reduction: int, depthwise: bool = False,
                 side_channels: int = 0, separable: bool = False) -> None:
        super().__init__()
        inner = channels // reduction
        self.branch = nn.Sequential(
            nn.Conv2d(channels + side_channels, inner, 1, bias=False), nn.BatchNorm2d(inner), nn.ReLU(inplace=True),
            _spatial_conv(inner, inner, kernel, depthwise, separable=separable), nn.BatchNorm2d(inner),
            nn.ReLU(inplace=True),
            nn.Conv2d(inner, channels, 1, bias=False), nn.BatchNorm2d(channels))


class SpatialBeliefUnit(nn.Module):
    """A large-kernel residual unit (the residual path) followed by two 1x1 convolutions (the belief path)."""

    def __init__(self, config: NetworkConfig, first: bool) -> None:
        super().__init__()
        side_channels = 0 if first else config.belief_channels
        if config.sb_reduction == 1:
            self.residual = ResidualUnit(config.width, config.sb_kernel, config.sb_depthwise, side_channels,
                                         config.sb_separable)
        else:
            self.residual = BottleneckUnit(config.width, config.sb_kernel, config.sb_reduction, config.sb_depthwise,
                                           side_channels, config.sb_separable)
        self.belief = nn.Sequential(nn.Conv2d(config.width, config.width, 1, bias=False),
                                    nn.BatchNorm2d(config.width), nn.ReLU(inplace=True),
                                    nn.Conv2d(config.width, config.belief_channels, 1))

    def forward(self, features: Tensor, previous_belief: Tensor | None) -> tuple[Tensor, Tensor]:
        features = self.residual(features, previous_belief)
        return features, self.belief(features)


def _stem(config: NetworkConfig) -> nn.Sequential:
    """The paper's 5x5 convolution; stride 2 makes it downsample, and stride 4 adds a strided 3x3 after it
    rather than one 5x5 with stride 4, which would skip input pixels. A "patch" stem is one convolution over
    non-overlapping stride x stride patches (:data:`vc.model.config.STEMS` says why)."""
    if config.stem == "patch":
        stride = config.stem_stride
        return nn.Sequential(nn.Conv2d(3, config.width, stride, stride, bias=False), nn.BatchNorm2d(config.width),
                             nn.ReLU(inplace=True))
    if config.stem_stride == 4:
        return nn.Sequential(_conv_bn_relu(3, config.width, 5, stride=2),
                             _conv_bn_relu(config.width, config.width, 3, stride=2))
    return _conv_bn_relu(3, config.width, 5, stride=config.stem_stride)


class ScenePoseNet(nn.Module):
    """Image (B, 3, H, W) in [0, 1] -> heat maps (B, C, ceil(H/s), ceil(W/s)) for the stem stride s and the
    config's ``heatmap_channels`` C (the layout of :mod:`vc.deploy.heatmaps`); a patch stem drops a last partial
    patch (floor), which never happens to inputs the codec accepts (multiples of s).

    ``forward`` returns ``{"heatmaps": ..., "beliefs": [...]}``. ``beliefs`` holds each SB unit's belief maps when
    the config asks for intermediate supervision and is empty otherwise, so a loss can always iterate over it.
    Heat maps have no output activation: they regress targets in [0, 1] with an MSE loss, and a sigmoid would
    have to push almost every pixel to -inf logits to reach the 0 background, flattening its own gradient there.
    Decoders clamp or threshold as they need.
    """

    def __init__(self, config: NetworkConfig) -> None:
        super().__init__()
        self.config = config
        self.stem = _stem(config)
        self.trunk = nn.Sequential(*(ResidualUnit(config.width, 3) for _ in range(config.residual_units)))
        self.sb_units = nn.ModuleList(SpatialBeliefUnit(config, first=i == 0) for i in range(config.sb_units))
        self.head = nn.Sequential(nn.Conv2d(config.sb_units * config.belief_channels, config.width, 1, bias=False),
                                  nn.BatchNorm2d(config.width), nn.ReLU(inplace=True),
                                  nn.Conv2d(config.width, config.heatmap_channels, 1))
        self._initialise()

    def _initialise(self) -> None:
        """He initialisation for the convolutions; the last BN of every residual branch starts at zero so that each
        unit starts as the identity (Goyal et al., 2017), which keeps the deep stack trainable from the first step;
        the layers that emit maps start near zero (``OUTPUT_INIT_STD``)."""
        for module in self.modules():
            if isinstance(module, nn.Conv2d):
                nn.init.kaiming_normal_(module.weight, mode="fan_in", nonlinearity="relu")
            elif isinstance(module, nn.BatchNorm2d):
                nn.init.ones_(module.weight)
                nn.init.zeros_(module.bias)
        for module in self.modules():
            if isinstance(module, _SideInputResidual):
                nn.init.zeros_(module.branch[-1].weight)
        for output in [self.head[-1], *(unit.belief[-1] for unit in self.sb_units)]:
            nn.init.normal_(output.weight, std=OUTPUT_INIT_STD)
            nn.init.zeros_(output.bias)

    def forward(self, image: Tensor) -> dict[str, Tensor | list[Tensor]]:
        if image.dim() != 4:  # a 3-D image would pass the convolutions (unbatched) and fail confusingly later
            raise ValueError(f"expected an image batch (B, 3, H, W), got shape {tuple(image.shape)}")
        features = self.trunk(self.stem((image - INPUT_CENTRE) / INPUT_HALF_RANGE))
        beliefs = []
        for unit in self.sb_units:
            features, belief = unit(features, beliefs[-1] if beliefs else None)
            beliefs.append(belief)
        heatmaps = self.head(torch.cat(beliefs, dim=1))
        return {"heatmaps": heatmaps, "beliefs": beliefs if self.config.intermediate_supervision else []}

    def receptive_field(self) -> int:
        """Side of the input window that one heat-map pixel depends on, in input pixels.

        Every spatial convolution lies on one path from the input to the heat maps (skips are identities, the
        belief and head paths are 1x1), and modules are registered in the order they run, so the field is the
        chain formula 1 + sum((k - 1) * dilation * product of the strides before that convolution), taken along
        the vertical axis (a separable k x 1 then 1 x k adds k - 1 along each axis: fields stay square).
        """
        field, stride = 1, 1
        for module in self.modules():
            if isinstance(module, nn.Conv2d):
                field += (module.kernel_size[0] - 1) * module.dilation[0] * stride
                stride *= module.stride[0]
        return field
