"""The network and its loss on the inputs at their edges: all-black, all-white, constant, single-pixel and
high-contrast images against empty, saturated, spiked and random targets (handedness maps at -1 too). Outputs,
loss and gradients stay finite."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from conftest import SMALL
from hard_case_settings import PROPERTY
from hypothesis import example, given
from hypothesis import strategies as st

from vc.deploy.heatmaps import HANDEDNESS_CHANNELS, HEATMAP_CHANNELS
from vc.model.loss import scene_pose_loss
from vc.model.network import ScenePoseNet

SIZE = 64
CELLS = SIZE // SMALL.stem_stride


@pytest.fixture(scope="module")
def network() -> ScenePoseNet:
    torch.manual_seed(0)
    return ScenePoseNet(SMALL)


@st.composite
def images(draw) -> torch.Tensor:
    kind = draw(st.sampled_from(["constant", "single pixel", "checkerboard", "random"]))
    level = draw(st.floats(0.0, 1.0, width=32))
    image = np.full((2, 3, SIZE, SIZE), level, np.float32)
    if kind == "single pixel":
        image[:, :, draw(st.integers(0, SIZE - 1)), draw(st.integers(0, SIZE - 1))] = 1.0 - level
    elif kind == "checkerboard":
        image[:, :, ::2, ::2] = 1.0 - level
    elif kind == "random":
        image = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).random(image.shape, np.float32)
    return torch.from_numpy(image)


@st.composite
def targets(draw) -> torch.Tensor:
    kind = draw(st.sampled_from(["empty", "saturated", "negative handedness", "spike", "random"]))
    maps = np.zeros((2, HEATMAP_CHANNELS, CELLS, CELLS), np.float32)
    if kind == "saturated":
        maps[:] = 1.0
    elif kind == "negative handedness":
        maps[:, HANDEDNESS_CHANNELS] = -1.0
    elif kind == "spike":
        maps[:, draw(st.integers(0, HEATMAP_CHANNELS - 1)), draw(st.integers(0, CELLS - 1)),
             draw(st.integers(0, CELLS - 1))] = 1.0
    elif kind == "random":
        maps = np.random.default_rng(draw(st.integers(0, 2**32 - 1))).random(maps.shape, np.float32)
        maps[:, HANDEDNESS_CHANNELS] = maps[:, HANDEDNESS_CHANNELS] * 2.0 - 1.0
    return torch.from_numpy(maps)


@PROPERTY
@given(image=images(), target=targets())
@example(image=torch.zeros(2, 3, SIZE, SIZE), target=torch.zeros(2, HEATMAP_CHANNELS, CELLS, CELLS))
@example(image=torch.ones(2, 3, SIZE, SIZE), target=torch.ones(2, HEATMAP_CHANNELS, CELLS, CELLS))
def test_edge_images_and_targets_give_a_finite_loss_and_gradients(network, image, target):
    network.zero_grad(set_to_none=True)
    outputs = network(image)
    assert outputs["heatmaps"].shape == target.shape and torch.isfinite(outputs["heatmaps"]).all()
    loss, terms = scene_pose_loss(outputs, target)
    loss.backward()
    assert torch.isfinite(loss) and all(np.isfinite(float(value)) for value in terms.values())
    assert all(torch.isfinite(parameter.grad).all() for parameter in network.parameters()
               if parameter.grad is not None)
