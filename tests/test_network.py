"""ScenePoseNet: output shapes per preset and stride, the receptive field against a measured one, the switches,
determinism and finite outputs on degenerate images, and the config's strict JSON round trip."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import pytest
import torch
from torch import nn

from vc.deploy.decode import RetiredSetting
from vc.deploy.heatmaps import ANATOMICAL_CHANNELS
from vc.model.config import (
    DEFAULT_ARCH,
    HEATMAP_CHANNELS,
    PRESETS,
    NetworkConfig,
    network_config,
)
from vc.model.network import ScenePoseNet
from vc.scenes.schema import RegionPlanSpec

TINY = NetworkConfig("tiny", stem_stride=2, width=4, residual_units=1, sb_units=2, sb_kernel=5, sb_depthwise=False,
                     belief_channels=3, intermediate_supervision=False)


def _net(config: NetworkConfig, seed: int = 0) -> ScenePoseNet:
    torch.manual_seed(seed)
    return ScenePoseNet(config)


@pytest.mark.parametrize("name", PRESETS)
def test_presets_give_heatmaps_at_the_output_stride(name):
    config = network_config(name)
    net = _net(config).eval()
    with torch.no_grad():
        out = net(torch.rand(2, 3, 32, 64))
    s = config.stem_stride
    assert out["heatmaps"].shape == (2, HEATMAP_CHANNELS, 32 // s, 64 // s)
    assert [b.shape for b in out["beliefs"]] == [out["heatmaps"].shape] * config.sb_units


#: The SB kernels' three factorings: dense k x k, depthwise + pointwise, k x 1 then 1 x k.
FACTORINGS = {"dense": {}, "depthwise": {"sb_depthwise": True}, "separable": {"sb_separable": True}}


@pytest.mark.parametrize("stride", [1, 2, 4])
@pytest.mark.parametrize("factoring", FACTORINGS)
def test_stem_strides_keep_exact_sizes_for_multiples_of_16(stride, factoring):
    net = _net(replace(TINY, stem_stride=stride, **FACTORINGS[factoring])).eval()
    with torch.no_grad():
        assert net(torch.rand(1, 3, 64, 128))["heatmaps"].shape == (1, HEATMAP_CHANNELS, 64 // stride, 128 // stride)
        # Other sizes round up: every layer pads to 'same', so the last partial window still yields a pixel.
        odd = net(torch.rand(1, 3, 50, 70))["heatmaps"].shape[-2:]
    assert tuple(odd) == (math.ceil(50 / stride), math.ceil(70 / stride))


@pytest.mark.parametrize("stride", [2, 4])
def test_patch_stems_give_heatmaps_at_their_stride_from_every_input_pixel(stride):
    net = _net(replace(TINY, stem_stride=stride, stem="patch")).eval()
    with torch.no_grad():
        assert net(torch.rand(1, 3, 64, 128))["heatmaps"].shape == (1, HEATMAP_CHANNELS, 64 // stride, 128 // stride)
    patchify = net.stem[0]
    assert (patchify.kernel_size, patchify.stride) == ((stride, stride), (stride, stride))  # no pixel skipped or
    # read twice


def test_the_patch_preset_is_the_default_but_for_its_stem():
    default, patch = network_config(DEFAULT_ARCH), network_config("fast-patch")
    assert replace(patch, name=default.name, stem=default.stem) == default
    assert ScenePoseNet(patch).receptive_field() < ScenePoseNet(default).receptive_field()


def _positive_weights(net: ScenePoseNet) -> None:
    """Make every weight positive and every BN the identity: with a positive input every ReLU passes and every
    path adds a positive term, so the gradient is nonzero exactly on the receptive field (no chance zeros)."""
    for module in net.modules():
        if isinstance(module, nn.Conv2d):
            nn.init.constant_(module.weight, 1.0 / module.weight[0].numel())
            if module.bias is not None:
                nn.init.zeros_(module.bias)
        elif isinstance(module, nn.BatchNorm2d):
            nn.init.ones_(module.weight)
            nn.init.zeros_(module.bias)


def _measured_receptive_field(net: ScenePoseNet, size: int) -> tuple[int, int]:
    image = torch.ones(1, 3, size, size, dtype=torch.float64, requires_grad=True)
    heatmaps = net(image)["heatmaps"]
    centre = heatmaps.shape[-1] // 2
    heatmaps[0, 0, centre, centre].backward()
    rows, cols = torch.nonzero(image.grad[0].abs().sum(0), as_tuple=True)
    assert rows.min() > 0 and cols.min() > 0 and rows.max() < size - 1 and cols.max() < size - 1, "field clipped"
    return int(rows.max() - rows.min() + 1), int(cols.max() - cols.min() + 1)


@pytest.mark.parametrize(("stride", "factoring", "stem"), [
    (1, "dense", "conv"), (2, "depthwise", "conv"), (4, "dense", "conv"), (4, "depthwise", "conv"),
    (2, "separable", "conv"), (4, "separable", "conv"), (4, "separable", "patch"), (2, "dense", "patch")])
def test_receptive_field_matches_the_gradient_footprint(stride, factoring, stem):
    net = _net(replace(TINY, stem_stride=stride, stem=stem, **FACTORINGS[factoring])).double().eval()
    _positive_weights(net)
    field = net.receptive_field()
    assert _measured_receptive_field(net, size=2 * field + 16) == (field, field)


def test_separable_kernels_see_the_same_window_for_2_over_k_of_the_weights():
    dense, separable = (ScenePoseNet(network_config(name)) for name in ("fast", "fast-sep"))
    assert separable.receptive_field() == dense.receptive_field()

    def large_kernel_weights(net: ScenePoseNet) -> int:
        return sum(m.weight.numel() for m in net.sb_units.modules()
                   if isinstance(m, nn.Conv2d) and max(m.kernel_size) == net.config.sb_kernel)

    assert large_kernel_weights(separable) * dense.config.sb_kernel == 2 * large_kernel_weights(dense)


def test_a_kernel_is_factored_one_way_at_most():
    with pytest.raises(ValueError, match="sb_separable and sb_depthwise"):
        replace(TINY, sb_separable=True, sb_depthwise=True)


def test_default_preset_sees_the_largest_person_of_a_region():
    # A region resizes people to target_person_px at its reference size; the tallest come out about twice that.
    largest_person_px = 2 * RegionPlanSpec().target_person_px
    assert ScenePoseNet(network_config(DEFAULT_ARCH)).receptive_field() >= largest_person_px


@pytest.mark.parametrize("sb_units", [1, 2, 3])
@pytest.mark.parametrize("supervised", [False, True])
def test_sb_units_and_intermediate_supervision_set_the_beliefs(sb_units, supervised):
    config = replace(TINY, sb_units=sb_units, belief_channels=HEATMAP_CHANNELS, intermediate_supervision=supervised)
    net = _net(config)
    assert len(net.sb_units) == sb_units
    out = net(torch.rand(2, 3, 32, 32))
    assert len(out["beliefs"]) == (sb_units if supervised else 0)
    assert all(belief.shape == out["heatmaps"].shape for belief in out["beliefs"])


def test_parameter_counts(capsys):
    counts = {name: sum(p.numel() for p in ScenePoseNet(config).parameters()) for name, config in PRESETS.items()}
    with capsys.disabled():
        print("\nScenePoseNet parameters: " + ", ".join(f"{name} {count:,}" for name, count in counts.items()))
    assert counts["fast-dw"] < counts["fast"] < counts["paper"]
    assert 25e6 < counts["paper"] < 35e6  # dominated by six dense 17x17 convolutions of 128 channels


def test_forward_is_deterministic():
    previous = torch.are_deterministic_algorithms_enabled()
    torch.use_deterministic_algorithms(True)
    try:
        config = replace(network_config(DEFAULT_ARCH), width=16)
        image = torch.rand(2, 3, 64, 64, generator=torch.Generator().manual_seed(1))
        for mode in (True, False):  # batch statistics, then running statistics
            first, second = _net(config).train(mode), _net(config).train(mode)
            a, b, c = first(image), first(image), second(image)
            assert torch.equal(a["heatmaps"], b["heatmaps"]) and torch.equal(a["heatmaps"], c["heatmaps"])
            assert all(torch.equal(x, y) for x, y in zip(a["beliefs"], c["beliefs"], strict=True))
    finally:
        torch.use_deterministic_algorithms(previous)


@pytest.mark.parametrize("value", [0.0, 1.0])
@pytest.mark.parametrize("training", [True, False])
def test_constant_images_give_finite_outputs_and_gradients(value, training):
    net = _net(replace(network_config(DEFAULT_ARCH), width=16)).train(training)
    out = net(torch.full((2, 3, 64, 64), value))
    loss = out["heatmaps"].square().mean() + sum(belief.square().mean() for belief in out["beliefs"])
    loss.backward()
    assert torch.isfinite(out["heatmaps"]).all()
    assert all(torch.isfinite(p.grad).all() for p in net.parameters() if p.grad is not None)


def test_rejects_an_unbatched_image():
    with pytest.raises(ValueError, match="image batch"):
        _net(TINY)(torch.rand(3, 32, 32))


@pytest.mark.parametrize("name", PRESETS)
def test_config_round_trips_through_json(name):
    config = network_config(name)
    assert NetworkConfig.from_dict(json.loads(json.dumps(config.to_dict()))) == config


@pytest.mark.parametrize("written", ["without the field", "with 19 maps"])
def test_configs_of_the_retired_19_map_layout_are_refused(written):
    """A config without ``heatmap_channels`` (written before the handedness maps) or with 19 describes a network of
    the retired layout: refused by name, never built as another network."""
    old = {key: value for key, value in network_config(DEFAULT_ARCH).to_dict().items() if key != "heatmap_channels"}
    old["belief_channels"] = ANATOMICAL_CHANNELS
    if written == "with 19 maps":
        old["heatmap_channels"] = ANATOMICAL_CHANNELS
    with pytest.raises(RetiredSetting, match="a network of 19 heat maps") as refused:
        NetworkConfig.from_dict(old)
    assert refused.value.field == "heatmap_channels"
    with pytest.raises(ValueError, match="heatmap_channels must be one of the layouts"):
        replace(network_config(DEFAULT_ARCH), heatmap_channels=ANATOMICAL_CHANNELS,
                belief_channels=ANATOMICAL_CHANNELS)


def test_config_rejects_bad_fields_and_values():
    data = TINY.to_dict()
    with pytest.raises(ValueError, match="depth"):  # a newer writer's field: never silently another network
        NetworkConfig.from_dict({**data, "depth": 3})
    predates_sb_units = {key: value for key, value in data.items() if key != "sb_units"}
    assert NetworkConfig.from_dict(predates_sb_units).sb_units == NetworkConfig.__dataclass_fields__["sb_units"].default
    with pytest.raises(ValueError, match="stem_stride"):
        replace(TINY, stem_stride=3)
    with pytest.raises(ValueError, match="odd"):
        replace(TINY, sb_kernel=8)
    with pytest.raises(ValueError, match="patch stem needs stem_stride 2 or 4"):
        replace(TINY, stem_stride=1, stem="patch")
    with pytest.raises(ValueError, match="stem must be one of"):
        replace(TINY, stem="pixel-shuffle")
    predates_stem = {key: value for key, value in data.items() if key != "stem"}
    assert NetworkConfig.from_dict(predates_stem).stem == "conv"  # the stem every network had before the field
    with pytest.raises(ValueError, match=f"belief_channels must be {HEATMAP_CHANNELS}"):
        replace(TINY, intermediate_supervision=True)
    with pytest.raises(ValueError, match="heatmap_channels must be"):
        replace(TINY, heatmap_channels=20)
    with pytest.raises(ValueError, match="unknown network preset"):
        network_config("huge")
