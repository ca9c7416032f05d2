"""Held-out synthetic accuracy of a trained region network, through the deployment decoder and the one metrics
implementation (:mod:`vc.evaluation.metrics`), so that what training reports is what the appliance will do.

Ground truth is each person's full (amodal) box, clipped to the input: the decoder's box is the person's expected
height at that position, not the visible part. People mostly hidden or cut off are ``ignore``: a detector is not
asked to find someone of whom less than :data:`MIN_VISIBLE_HEIGHT` of the height shows, or whose centre is off
the input, nor penalised for finding them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch
from tqdm import tqdm

from vc.deploy.decode import DecodeConfig, DecodedPerson, decode
from vc.evaluation.metrics import Evaluation, ImageResult, evaluate
from vc.model.data import Sample, read_sample
from vc.model.network import ScenePoseNet

#: Fraction of a person's full height that must be visible for the evaluation to ask for them.
MIN_VISIBLE_HEIGHT = 0.5
EVALUATION_BATCH = 4


def _xyxy(box_xywh: list[float]) -> np.ndarray:
    x, y, width, height = box_xywh
    return np.array([x, y, x + width, y + height])


def asked_for(annotation: dict, input_size: tuple[int, int]) -> bool:
    """Whether the evaluation counts a person (see the module docstring)."""
    width, height = input_size
    centre = annotation.get("center")
    if centre is None or not (-0.5 <= centre[0] <= width - 0.5 and -0.5 <= centre[1] <= height - 0.5):
        return False
    return annotation["bbox"][3] >= MIN_VISIBLE_HEIGHT * annotation["amodal_bbox"][3]


def image_result(annotations: list[dict], instances: np.ndarray, people: list[DecodedPerson],
                 stride: int) -> ImageResult:
    """One sample's truth and decoded people in the metrics' terms (boxes clipped to the input)."""
    height, width = instances.shape
    limits = np.array([-0.5, -0.5, width - 0.5, height - 0.5])
    boxes = np.array([person.box for person in people]).reshape(-1, 4)
    boxes = np.clip(boxes, limits[[0, 1, 0, 1]], limits[[2, 3, 2, 3]])
    return ImageResult(
        truth_boxes=np.array([_xyxy(a["amodal_bbox"]) for a in annotations]).reshape(-1, 4),
        boxes=boxes,
        scores=np.array([person.score for person in people]),
        truth_keypoints=np.array([np.reshape(a["keypoints"], (-1, 3)) for a in annotations]).reshape(-1, 17, 3),
        keypoints=np.array([person.keypoints for person in people]).reshape(-1, 17, 3),
        truth_masks=[instances == a["instance_id"] for a in annotations],
        masks=[np.repeat(np.repeat(person.mask_cells, stride, axis=0), stride, axis=1)[:height, :width]
               for person in people],
        truth_ignore=np.array([not asked_for(a, (width, height)) for a in annotations], bool),
    )


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
