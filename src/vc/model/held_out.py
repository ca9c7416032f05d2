"""Held-out synthetic accuracy of a trained region network, through the deployment decoder and the one metrics
implementation (:mod:`vc.evaluation.metrics`) and the render protocol (:mod:`vc.evaluation.renders`), so that
what training reports is what the appliance will do.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch
from tqdm import tqdm

from vc.deploy.decode import DecodeConfig, decode
from vc.evaluation.metrics import Evaluation, ImageResult, evaluate
from vc.evaluation.renders import image_result
from vc.model.network import ScenePoseNet
from vc.render.dataset import Sample, read_sample

EVALUATION_BATCH = 4


@dataclass
class RegionEvaluation:
    evaluation: Evaluation
    images: list[ImageResult]


#: Heat maps of a batch of region inputs: (N, H, W, 3) uint8 RGB -> (N, C, h, w) float.
HeatmapSource = Callable[[np.ndarray], np.ndarray]


def evaluate_source(heatmaps_of: HeatmapSource, samples: list[Sample], decode_config: DecodeConfig,
                    expected_height_px: np.ndarray, show_progress: bool = True,
                    description: str = "evaluate") -> RegionEvaluation:
    """Score any source of heat maps (a PyTorch network, an onnxruntime session) on whole held-out inputs,
    decoded as deployment decodes them."""
    results: list[ImageResult] = []
    with tqdm(total=len(samples), desc=description, unit="img", disable=not show_progress, leave=False) as bar:
        for start in range(0, len(samples), EVALUATION_BATCH):
            batch = samples[start:start + EVALUATION_BATCH]
            images, instances = zip(*(read_sample(sample) for sample in batch), strict=True)
            for sample, mask, maps in zip(batch, instances, heatmaps_of(np.stack(images)), strict=True):
                people = decode(maps, decode_config, expected_height_px)
                results.append(image_result(sample.annotations, mask, people, decode_config.stride))
            bar.update(len(batch))
    return RegionEvaluation(evaluate(results), results)


@torch.no_grad()
def evaluate_network(net: ScenePoseNet, samples: list[Sample], decode_config: DecodeConfig,
                     expected_height_px: np.ndarray, device: torch.device, show_progress: bool = True,
                     description: str = "evaluate") -> RegionEvaluation:
    """Run ``net`` on whole held-out inputs, decode as deployment does and score the result."""
    was_training = net.training
    net.eval()

    def heatmaps_of(images: np.ndarray) -> np.ndarray:
        batch = torch.from_numpy(images).to(device).permute(0, 3, 1, 2).float() / 255.0
        return net(batch)["heatmaps"].float().cpu().numpy()

    try:
        return evaluate_source(heatmaps_of, samples, decode_config, expected_height_px, show_progress, description)
    finally:
        net.train(was_training)
