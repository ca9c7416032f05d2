"""The paper's loss: alpha * MSE(detection) + beta * mean MSE(pose) + gamma * MSE(segmentation), plus
delta * mean MSE(handedness) for the maps that tell which member of each keypoint pair is the left one
(:mod:`vc.deploy.heatmaps`), and, for networks that emit them, epsilon times the centre offsets' L1 error weighed
by the target mask (an offset means something only on a person's pixels; L1, as in Panoptic-DeepLab, so that the
cells on the border between two people, whose owner is a coin toss, do not dominate). For networks with a fine
centre map, alpha times its MSE too (its Gaussians are as wide in pixels as the coarse map's, so the two errors
are of one size): the centre map then takes twice its share of the loss. Weighing the mean of the two instead
kept more of the held-out renders' PCKh but less of the real frames, where pose and people are judged
(docs/decisions/0010-fine-centre-map.md). For networks with a head map, alpha times its MSE too (a person's second
peak), and the size map's L1 weighed by the mask in the offsets' term (it scales the offsets at a head).

Each term is a mean squared error over its heat-map pixels (the pose and handedness terms the mean over their
maps; the offsets' term their mask-weighed absolute error, averaged likewise).
With intermediate supervision every SB unit's belief maps are held to the same targets and their losses added
(as in convolutional pose machines), so early units learn usable beliefs instead of whatever helps the last one.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import torch
from torch import Tensor

from vc.deploy.heatmaps import (
    CENTRE_CHANNEL,
    CENTRE_OFFSET_CHANNELS,
    FINE_CENTRE_CHANNELS,
    FINE_CHANNELS,
    HANDEDNESS_CHANNELS,
    HEAD_CHANNEL,
    HEAD_CHANNELS,
    KEYPOINT_CHANNELS,
    MASK_CHANNEL,
    SIZE_CHANNEL,
)


@dataclass(frozen=True)
class LossWeights:
    """alpha, beta, gamma of the paper's loss and delta of the handedness term.

    A keypoint Gaussian covers about (0.025/0.08)^2 = 1/10 of a centre Gaussian's area (model.codec), so its
    per-pixel MSE is about ten times smaller; ``pose`` makes up for that so that pose is not learned last.
    """

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    detection: float = 1.0
    pose: float = 10.0
    segmentation: float = 1.0
    handedness: float = 1.0
    # The offsets' L1 over a person's cells is about their error in heights (0.05: a cell of an 80 px person) times
    # the share of cells people cover, the size of the other terms' MSE once trained.
    centre_offsets: float = 1.0

    def to_dict(self) -> dict:
        return asdict(self)


def heatmap_terms(prediction: Tensor, targets: Tensor) -> dict[str, Tensor]:
    """The terms of one prediction (B, C, h, w) against its targets (same shape), unweighted: C one of the
    layouts of :mod:`vc.deploy.heatmaps`, the ``centre_offsets`` term only where it has the offset maps, the
    ``fine_centre`` term only where it has the fine centre map, and the ``head`` and ``size`` terms only where it
    has the head and size maps."""
    if prediction.shape != targets.shape:
        raise ValueError(f"prediction {tuple(prediction.shape)} and targets {tuple(targets.shape)} differ in shape")
    squared = (prediction[:, :CENTRE_OFFSET_CHANNELS.start] - targets[:, :CENTRE_OFFSET_CHANNELS.start]).square()
    terms = {"detection": squared[:, CENTRE_CHANNEL].mean(),
             "pose": squared[:, KEYPOINT_CHANNELS].mean(),  # = mean over keypoints of each map's MSE
             "segmentation": squared[:, MASK_CHANNEL].mean(),
             "handedness": squared[:, HANDEDNESS_CHANNELS].mean()}
    if prediction.shape[1] >= CENTRE_OFFSET_CHANNELS.stop:
        error = (prediction[:, CENTRE_OFFSET_CHANNELS] - targets[:, CENTRE_OFFSET_CHANNELS]).abs()
        terms["centre_offsets"] = (error * targets[:, MASK_CHANNEL, None]).mean()
    if prediction.shape[1] >= FINE_CHANNELS:
        terms["fine_centre"] = (prediction[:, FINE_CENTRE_CHANNELS] - targets[:, FINE_CENTRE_CHANNELS]).square().mean()
    if prediction.shape[1] == HEAD_CHANNELS:
        terms["head"] = (prediction[:, HEAD_CHANNEL] - targets[:, HEAD_CHANNEL]).square().mean()
        terms["size"] = ((prediction[:, SIZE_CHANNEL] - targets[:, SIZE_CHANNEL]).abs()
                         * targets[:, MASK_CHANNEL]).mean()
    return terms


def scene_pose_loss(outputs: dict[str, Tensor | list[Tensor]], targets: Tensor,
                    weights: LossWeights = LossWeights()) -> tuple[Tensor, dict[str, float]]:
    """The weighted loss of the final heat maps plus, with intermediate supervision, of every belief stage.

    Returns the scalar to minimise and the final heat maps' unweighted terms (for logging).
    """
    total = torch.zeros((), dtype=targets.dtype, device=targets.device)
    final_terms: dict[str, Tensor] = {}
    for stage, prediction in enumerate([*outputs["beliefs"], outputs["heatmaps"]]):
        terms = heatmap_terms(prediction, targets)
        total = total + (weights.detection * (terms["detection"] + terms.get("fine_centre", 0.0)
                                              + terms.get("head", 0.0))
                         + weights.pose * terms["pose"]
                         + weights.segmentation * terms["segmentation"] + weights.handedness * terms["handedness"]
                         + weights.centre_offsets * (terms.get("centre_offsets", 0.0) + terms.get("size", 0.0)))
        if stage == len(outputs["beliefs"]):
            final_terms = terms
    return total, {name: float(value.detach()) for name, value in final_terms.items()}
