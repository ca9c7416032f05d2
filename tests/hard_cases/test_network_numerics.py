"""The network and its loss on the inputs at their edges: all-black, all-white and constant images, empty and
saturated targets. Outputs, loss and gradients stay finite."""

from __future__ import annotations

import pytest
import torch
from conftest import SMALL
from hard_case_settings import THOROUGH

from vc.deploy.heatmaps import HEATMAP_CHANNELS
from vc.model.loss import scene_pose_loss
from vc.model.network import ScenePoseNet

SIZE = 64
LEVELS = [0.0, 1.0, 0.5, 1e-6, 1.0 - 1e-6]
TARGETS = {"empty": 0.0, "saturated": 1.0, "negative handedness": -1.0}


@pytest.fixture(scope="module")
def network() -> ScenePoseNet:
    torch.manual_seed(0)
    return ScenePoseNet(SMALL)


@pytest.mark.parametrize("level", LEVELS * (20 if THOROUGH else 1))
@pytest.mark.parametrize("target", list(TARGETS))
def test_constant_images_and_edge_targets_give_a_finite_loss_and_gradients(network, level, target):
    network.zero_grad(set_to_none=True)
    images = torch.full((2, 3, SIZE, SIZE), level)
    outputs = network(images)
    targets = torch.full_like(outputs["heatmaps"], TARGETS[target])
    assert outputs["heatmaps"].shape[1] == HEATMAP_CHANNELS and torch.isfinite(outputs["heatmaps"]).all()
    loss, terms = scene_pose_loss(outputs, targets)
    loss.backward()
    assert torch.isfinite(loss) and all(torch.isfinite(torch.tensor(value)) for value in terms.values())
    assert all(torch.isfinite(parameter.grad).all() for parameter in network.parameters()
               if parameter.grad is not None)
