"""The keypoint model: a small network per compile, trained on the compile's renders, that reads each person's 17
keypoints again from their own crop (:mod:`vc.deploy.crop_pose` runs it).

Why a model of its own: the region networks find people and place their keypoints in one pass over the region, and
their limbs are where they are weakest, on their own held-out renders too (TUD-Stadtmitte's r0: wrists within half
a head size 0.55, ankles 0.49). A network that sees one person at a time places a held-out render's keypoints within
half a head size 0.82 of the time on TUD-Stadtmitte (image order), and agrees with the reference pose model on its
real people more often; on PETS09's small people seen from above it is sure of little and changes nothing. The
runtime reads it only for people :data:`~vc.deploy.crop_pose.MIN_READ_HEIGHT_PX` and taller, and a compile trains it
where most of the scene's people are that tall (``train.crop_pose: auto``, :data:`MIN_TALL_SHARE`;
docs/decisions/0039-keypoints-from-the-crop.md, docs/decisions/0040-keypoint-model-by-size.md).

1. **Crops**: every rendered person seen whole (the facing model's :data:`~vc.model.facing.MIN_VISIBLE_SHARE` and
   :data:`~vc.model.facing.MIN_HEIGHT_PX`) who would stand at least :data:`TRAINED_HEIGHT_SHARE` of the runtime's
   height in the frame, cut by the crop graph at :data:`~vc.deploy.crop_pose.CROP_SIZE`
   around a box drawn as the region networks draw one: the amodal box with its centre moved and its height scaled
   by :data:`BOX_JITTER` of its height (normal draws, seeded), framed as :func:`~vc.deploy.facing.crop_rois`
   frames it. Labels: the 17 keypoints in crop pixels, each left/right pair in image order.
2. **Network** (:class:`CropPoseNet`): an encoder to 1/16 of the crop whose last convolutions are dilated (the
   whole figure in view at once), and a decoder back to :data:`~vc.deploy.crop_pose.MAP_STRIDE` with the encoder's
   maps beside it, one heat map per keypoint.
3. **Training**: Gaussian targets (:data:`SIGMA_CELLS`), squared error over the labelled keypoints weighted toward
   each target's peak (:data:`PEAK_WEIGHT`), each crop in the camera's look (:func:`~vc.model.facing.camera_look`)
   and mirrored half the time (a mirror exchanges each pair's image order), :data:`SAMPLES_SEEN` crops in all,
   AdamW with a one-cycle schedule, seeded; the dataset's held-out shards measure it (PCKh, in image order).
4. **Export** (:func:`vc.model.export.export_crop_pose`): the crop graph and the network as one ONNX graph, a frame
   and the crops' rectangles in, the heat maps out.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import onnxruntime as ort
import torch
from torch import Tensor, nn
from tqdm import tqdm

from vc.deploy.crop_pose import CROP_SIZE, MAP_STRIDE, keypoints_of_maps
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT
from vc.io import read_image
from vc.keypoints import COCO_KEYPOINTS
from vc.model.facing import MIN_HEIGHT_PX, MIN_VISIBLE_SHARE, camera_look, crop_graph
from vc.render.dataset import Sample, open_region, read_manifest

#: Where a run keeps the keypoint model and what it measured (``vc-train`` writes them, ``vc-export`` ships them).
CROP_POSE_MODEL, CROP_POSE_REPORT = "crop_pose.onnx", "crop_pose.json"
#: Fewer whole rendered people than this leave the model unlearnt: a run trains none.
MIN_CROP_POSE_CROPS = 1000
#: How far a box drawn by the region networks departs from the amodal box (a share of its height, one sigma).
BOX_JITTER = 0.05
#: The Gaussian targets' sigma, in heat-map cells.
SIGMA_CELLS = 1.0
#: The network's widths, at 1/2, 1/4, 1/8 and 1/16 of the crop.
WIDTHS = (16, 24, 48, 64)
#: Training schedule: crops seen in all, whatever the renders hold. With :data:`PEAK_WEIGHT`, 200 000 read
#: TUD-Stadtmitte's held-out renders at PCKh 0.84 (docs/decisions/0040-keypoint-model-by-size.md); twice as many read
#: them at 0.87 and its real people closer to the reference on every seed and half, for 5 more minutes of a compile
#: (docs/decisions/0051-the-keypoint-model-learns-longer.md).
SAMPLES_SEEN = 400_000
BATCH = 64
LEARNING_RATE = 2e-3
#: Each cell's squared error weighs 1 + this x its target: the few cells near a keypoint outweigh the many far from
#: it: with plain squared error 100 000 crops leave the maps near 0 (PCKh 0.3), with this 0.80 (0040).
PEAK_WEIGHT = 10.0
#: The squared error is small (most of a map is 0): scaled so that AdamW's steps are not lost to its epsilon.
LOSS_SCALE = 100.0
#: The model learns from the people who would be at least this share of the runtime's
#: :data:`~vc.deploy.crop_pose.MIN_READ_HEIGHT_PX` in the frame: a box drawn short of a person still reads them.
TRAINED_HEIGHT_SHARE = 0.8
#: A compile left to decide (``train.crop_pose: auto``) trains the model where at least this share of its whole
#: rendered people are tall enough to be read: elsewhere it would cost a compile minutes for few people (PETS09: 16 %
#: of them, for +0.001 agreement; 0040).
MIN_TALL_SHARE = 0.5
_MIRROR = [True] * len(PAIRS)


@dataclass(frozen=True)
class PoseCrops:
    """Crops (N, 96, 48, 3) uint8, their keypoints (N, 17, 3: x, y in crop pixels, pairs in image order, and the
    label's visibility, 0 where not labelled) and each person's amodal height in crop pixels (N,)."""

    crops: np.ndarray
    keypoints: np.ndarray
    heights: np.ndarray

    def __len__(self) -> int:
        return len(self.crops)


def _conv(inputs: int, outputs: int, stride: int = 1, dilation: int = 1) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(inputs, outputs, 3, stride, padding=dilation, dilation=dilation, bias=False),
                         nn.BatchNorm2d(outputs), nn.ReLU(inplace=True))


class CropPoseNet(nn.Module):
    """Step 2: an encoder to 1/16 (its last two convolutions dilated) and a decoder back to 1/2 of the crop."""

    def __init__(self, widths: tuple[int, int, int, int] = WIDTHS) -> None:
        super().__init__()
        half, quarter, eighth, sixteenth = widths
        self.to_half = nn.Sequential(_conv(3, half, 2), _conv(half, half))
        self.to_quarter = nn.Sequential(_conv(half, quarter, 2), _conv(quarter, quarter))
        self.to_eighth = nn.Sequential(_conv(quarter, eighth, 2), _conv(eighth, eighth))
        self.to_sixteenth = nn.Sequential(_conv(eighth, sixteenth, 2), _conv(sixteenth, sixteenth, dilation=2),
                                          _conv(sixteenth, sixteenth, dilation=2))
        self.up_to_eighth = _conv(sixteenth + eighth, eighth)
        self.up_to_quarter = _conv(eighth + quarter, quarter)
        self.up_to_half = _conv(quarter + half, half)
        self.maps = nn.Conv2d(half, len(COCO_KEYPOINTS), 1)

    def forward(self, crops: Tensor) -> Tensor:
        half = self.to_half(crops)
        quarter = self.to_quarter(half)
        eighth = self.to_eighth(quarter)
        deep = self.to_sixteenth(eighth)
        eighth = self.up_to_eighth(torch.cat([nn.functional.interpolate(deep, scale_factor=2.0), eighth], 1))
        quarter = self.up_to_quarter(torch.cat([nn.functional.interpolate(eighth, scale_factor=2.0), quarter], 1))
        return self.maps(self.up_to_half(torch.cat([nn.functional.interpolate(quarter, scale_factor=2.0), half], 1)))


def _seen_whole(annotation: dict) -> bool:
    """A rendered person the model learns from: tall enough and seen whole (the facing model's thresholds)."""
    amodal_height = annotation["amodal_bbox"][3]
    return amodal_height >= MIN_HEIGHT_PX and annotation["bbox"][3] >= MIN_VISIBLE_SHARE * amodal_height


def crops_of(samples: list[Sample], rng: np.random.Generator, min_height: float = 0.0) -> PoseCrops:
    """Every whole person of ``samples`` at least ``min_height`` render pixels tall, cut around a jittered box, with
    image-ordered labels (step 1)."""
    session = ort.InferenceSession(crop_graph(CROP_SIZE).SerializeToString(), providers=["CPUExecutionProvider"])
    crops, keypoints, heights = [], [], []
    for sample in samples:
        people = [annotation for annotation in sample.annotations
                  if _seen_whole(annotation) and annotation["amodal_bbox"][3] >= min_height]
        if not people:
            continue
        boxes, labels = [], []
        for annotation in people:
            x, y, width, height = annotation["amodal_bbox"]
            centre = np.array([x + width / 2, y + height / 2]) + rng.normal(0.0, BOX_JITTER, 2) * height
            tall = height * np.exp(rng.normal(0.0, BOX_JITTER))
            boxes.append([centre[0] - width / 2, centre[1] - tall / 2, centre[0] + width / 2, centre[1] + tall / 2])
            anatomical = np.reshape(annotation["keypoints"], (17, 3)).astype(np.float64)
            labels.append(swap_pairs(anatomical, [not first for first in annotation["left_is_image_left"]]))
        rois = crop_rois(np.array(boxes))
        image = read_image(sample.image_path)
        cut = session.run(None, {FRAME_INPUT: image[None], ROIS_INPUT: rois})[0]
        crops.append(np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255.0), 0, 255).astype(np.uint8))
        bins = np.stack([(rois[:, 2] - rois[:, 0]) / CROP_SIZE[0], (rois[:, 3] - rois[:, 1]) / CROP_SIZE[1]], 1)
        for person, roi, size, annotation in zip(labels, rois, bins, people, strict=True):
            person[:, :2] = (person[:, :2] + 0.5 - roi[:2]) / size - 0.5  # frame pixels -> crop pixels (centres)
            keypoints.append(person)
            heights.append(annotation["amodal_bbox"][3] / size[1])
    if not crops:
        return PoseCrops(np.zeros((0, CROP_SIZE[1], CROP_SIZE[0], 3), np.uint8), np.zeros((0, 17, 3), np.float32),
                         np.zeros(0, np.float32))
    return PoseCrops(np.concatenate(crops), np.array(keypoints, np.float32), np.array(heights, np.float32))


def dataset_crops(dataset: Path, seed: int, min_frame_height: float = 0.0) -> tuple[PoseCrops, PoseCrops]:
    """The training and held-out crops of every region of a rendered ``dataset``, their boxes drawn with ``seed``:
    the people who would be at least ``min_frame_height`` pixels tall in the camera's frame."""
    rng = np.random.default_rng(seed)
    train, held_out = [], []
    for region, entry in read_manifest(dataset).get("regions", {}).items():
        data = open_region(dataset, region)
        min_height = min_frame_height * entry["input_size"][1] / entry["crop_window"][3]  # frame -> render pixels
        train.append(crops_of(data.train, rng, min_height))
        held_out.append(crops_of(data.held_out, rng, min_height))
    return _joined(train), _joined(held_out)


def frame_heights(dataset: Path) -> np.ndarray:
    """How tall each whole rendered person of ``dataset``'s training shards would stand in the camera's frame
    (pixels): what the keypoint model would read of the scene."""
    heights = []
    for region, entry in read_manifest(dataset).get("regions", {}).items():
        to_frame = entry["crop_window"][3] / entry["input_size"][1]
        heights += [annotation["amodal_bbox"][3] * to_frame for sample in open_region(dataset, region).train
                    for annotation in sample.annotations if _seen_whole(annotation)]
    return np.array(heights, np.float64)


def _joined(parts: list[PoseCrops]) -> PoseCrops:
    return PoseCrops(*(np.concatenate([getattr(part, name) for part in parts])
                       for name in ("crops", "keypoints", "heights")))


def heatmap_targets(keypoints: np.ndarray) -> tuple[Tensor, Tensor]:
    """Gaussian maps (N, 17, h, w) of image-ordered ``keypoints`` (N, 17, 3) in crop pixels, and which are labelled
    (N, 17)."""
    cells = (keypoints[..., :2] + 0.5) / MAP_STRIDE - 0.5
    rows, columns = np.mgrid[0:CROP_SIZE[1] // MAP_STRIDE, 0:CROP_SIZE[0] // MAP_STRIDE].astype(np.float32)
    maps = np.exp(-((columns - cells[..., 0, None, None]) ** 2 + (rows - cells[..., 1, None, None]) ** 2)
                  / (2 * SIGMA_CELLS**2))
    return torch.from_numpy(maps.astype(np.float32)), torch.from_numpy((keypoints[..., 2] > 0).astype(np.float32))


def mirrored(crops: np.ndarray, keypoints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Crops mirrored left to right and their keypoints with them: a mirror exchanges each pair's image order."""
    flipped = keypoints.copy()
    flipped[..., 0] = CROP_SIZE[0] - 1 - flipped[..., 0]
    return crops[:, :, ::-1], swap_pairs(flipped, np.broadcast_to(_MIRROR, (len(keypoints), len(PAIRS))))


def _batch(crops: np.ndarray) -> Tensor:
    return torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2).float() / 255.0


def read_keypoints(net: CropPoseNet, crops: np.ndarray) -> np.ndarray:
    """What ``net`` reads of ``crops`` (N, 96, 48, 3): keypoints (N, 17, 3) in crop pixels, read as the runtime
    reads them."""
    net.eval()
    whole = np.array([[0.0, 0.0, CROP_SIZE[0], CROP_SIZE[1]]])
    with torch.no_grad():
        maps = [net(_batch(crops[start:start + 256])).numpy() for start in range(0, len(crops), 256)]
    every = np.concatenate(maps) if maps else np.zeros((0, 17, CROP_SIZE[1] // MAP_STRIDE, CROP_SIZE[0] // MAP_STRIDE))
    return keypoints_of_maps(every, np.repeat(whole, len(every), axis=0))


@dataclass(frozen=True)
class CropPoseResult:
    net: CropPoseNet
    held_out_pckh: float | None  # share of held-out labelled keypoints within half a head size; None without any
    held_out_pckh_per_keypoint: list[float] | None
    train_crops: int
    held_out_crops: int
    seconds: float

    def to_dict(self) -> dict:
        return {"held_out_pckh": None if self.held_out_pckh is None else round(self.held_out_pckh, 4),
                "held_out_pckh_per_keypoint": self.held_out_pckh_per_keypoint,
                "train_crops": self.train_crops, "held_out_crops": self.held_out_crops,
                "seconds": round(self.seconds, 1)}


def pckh(read: np.ndarray, crops: PoseCrops) -> tuple[float, list[float]] | None:
    """PCKh@0.5 of keypoints ``read`` (N, 17, 3) against ``crops``' labels, overall and per keypoint (image order)."""
    labelled = crops.keypoints[..., 2] > 0
    if not labelled.any():
        return None
    near = (np.linalg.norm(read[..., :2] - crops.keypoints[..., :2], axis=-1)
            <= 0.5 * HEAD_FRACTION_OF_HEIGHT * crops.heights[:, None])
    per = [round(float(near[labelled[:, k], k].mean()), 4) if labelled[:, k].any() else None
           for k in range(len(COCO_KEYPOINTS))]
    return float(near[labelled].mean()), per


def train_crop_pose(train: PoseCrops, held_out: PoseCrops, seed: int, samples: int = SAMPLES_SEEN,
                    widths: tuple[int, int, int, int] = WIDTHS, bf16_autocast: bool = False,
                    channels_last: bool = False, show_progress: bool = True) -> CropPoseResult:
    """Train a :class:`CropPoseNet` of ``widths`` on ``samples`` crops drawn from ``train`` (each once before any
    twice) and measure it on ``held_out`` (step 3); the same ``seed`` gives the same weights on one kind of CPU.
    ``bf16_autocast`` and ``channels_last``: the forward pass in bfloat16, in NHWC order, as the region networks
    train where the CPU has bf16 instructions (0006). A compile trains this model in fp32: in bf16 it learns in 0.7x
    the time and reads real people a little further from the reference on every seed
    (docs/decisions/0052-the-keypoint-model-stays-in-fp32.md)."""
    if len(train) < BATCH:
        raise ValueError(f"{len(train)} whole rendered people; the keypoint model needs {BATCH} or more")
    start = time.perf_counter()
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    layout = torch.channels_last if channels_last else torch.contiguous_format
    net = CropPoseNet(widths).to(memory_format=layout)
    steps = max(1, samples // BATCH)
    optimiser = torch.optim.AdamW(net.parameters(), LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, LEARNING_RATE, total_steps=steps)
    order = np.zeros(0, np.int64)
    net.train()
    for _ in tqdm(range(steps), desc="keypoints from the crop", unit="step", disable=not show_progress,
                  leave=False):
        if len(order) < BATCH:
            order = rng.permutation(len(train))
        chosen, order = order[:BATCH], order[BATCH:]
        looks = np.stack([camera_look(crop, rng) for crop in train.crops[chosen]])
        keypoints = train.keypoints[chosen]
        flip = rng.random(len(chosen)) < 0.5
        looks[flip], keypoints[flip] = mirrored(looks[flip], keypoints[flip])
        targets, labelled = heatmap_targets(keypoints)
        with torch.autocast("cpu", dtype=torch.bfloat16, enabled=bf16_autocast):
            maps = net(_batch(looks).contiguous(memory_format=layout))
        squared = (maps.float() - targets) ** 2 * (1.0 + PEAK_WEIGHT * targets)
        loss = (squared.mean(dim=(2, 3)) * labelled).sum() / labelled.sum().clamp(min=1.0)
        optimiser.zero_grad()
        (loss * LOSS_SCALE).backward()
        optimiser.step()
        schedule.step()
    measured = pckh(read_keypoints(net, held_out.crops), held_out) if len(held_out) else None
    return CropPoseResult(net, None if measured is None else measured[0], None if measured is None else measured[1],
                          len(train), len(held_out), time.perf_counter() - start)
