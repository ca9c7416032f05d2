"""A second look at each person: a small network reading all 17 keypoints from the person's own crop, trained on a
compile's renders (frozen, issue 57 item 4: TUD-Stadtmitte's limbs).

    PYTHONPATH=src:. python experiments/2026-12-01-keypoint-crops/crops.py RENDERS OUT.pt [EPOCHS [WIDTHS]] > OUT.json

WIDTHS: the network's four widths, comma-separated (default 16,24,48,64).

1. **Crops**: every rendered person seen whole (visible box at least 0.8 of the amodal box's height, amodal height
   at least 20 px), cut at CROP (48 x 96) around a box drawn as a detector draws it: the amodal box, its height
   and centre jittered by a few per cent, framed as the facing model frames it (``crop_rois``: 1.1 times the
   box's height, twice as tall as wide). Labels: the 17 keypoints in crop pixels, each left/right pair in *image*
   order (which member is the left one stays the facing model's question).
2. **Network**: an encoder to 1/16 with dilated convolutions (the whole figure in view) and a decoder back to 1/2,
   one heat map per keypoint; Gaussian targets (sigma one output cell), squared error over labelled keypoints.
   Trained with the facing model's camera look and mirror (a mirror exchanges each pair's image order).
3. **Reading**: each map's maximum, moved a quarter cell toward its larger neighbour on each axis.
4. **Held-out renders**: PCKh (within half a head size, a head 1/8 of the amodal height) per keypoint in image
   order, the network against the labels.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import torch
from torch import Tensor, nn

from vc.deploy.facing import crop_rois
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.io import read_image
from vc.keypoints import COCO_KEYPOINTS
from vc.model.facing import camera_look
from vc.render.dataset import open_region, read_manifest

CROP = (48, 96)  # width, height
STRIDE = 2
MAPS = (CROP[1] // STRIDE, CROP[0] // STRIDE)
SIGMA_CELLS = 1.0
JITTER = 0.05
BATCH = 64
LEARNING_RATE = 2e-3
HEAD_FRACTION = 1 / 8
SIDE_SWAP = [True] * len(PAIRS)


def crop_matrix(roi: np.ndarray) -> np.ndarray:
    """The affine map from crop pixels (centres at integers) to frame pixels (centres at integers) of ``roi``
    (x0, y0, x1, y1 in pixel edges)."""
    scale_x, scale_y = (roi[2] - roi[0]) / CROP[0], (roi[3] - roi[1]) / CROP[1]
    return np.array([[scale_x, 0, roi[0] + 0.5 * scale_x - 0.5], [0, scale_y, roi[1] + 0.5 * scale_y - 0.5]])


def cut(image: np.ndarray, roi: np.ndarray) -> np.ndarray:
    return cv2.warpAffine(image, crop_matrix(roi), CROP, flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                          borderMode=cv2.BORDER_REPLICATE)


def to_crop(points: np.ndarray, roi: np.ndarray) -> np.ndarray:
    matrix = crop_matrix(roi)
    return (points - matrix[:, 2]) / np.array([matrix[0, 0], matrix[1, 1]])


def to_frame(points: np.ndarray, roi: np.ndarray) -> np.ndarray:
    matrix = crop_matrix(roi)
    return points * np.array([matrix[0, 0], matrix[1, 1]]) + matrix[:, 2]


def people(samples, rng: np.random.Generator, jitter: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crops (N, 96, 48, 3) uint8, image-ordered keypoints in crop pixels with labels (N, 17, 3), heights (N,)."""
    crops, points, heights = [], [], []
    for sample in samples:
        chosen = [a for a in sample.annotations
                  if a["amodal_bbox"][3] >= 20 and a["bbox"][3] >= 0.8 * a["amodal_bbox"][3]]
        if not chosen:
            continue
        image = read_image(sample.image_path)
        for annotation in chosen:
            x, y, width, height = annotation["amodal_bbox"]
            centre = np.array([x + width / 2, y + height / 2]) + rng.normal(0, jitter, 2) * height
            tall = height * np.exp(rng.normal(0, jitter))
            box = np.array([centre[0] - width / 2, centre[1] - tall / 2, centre[0] + width / 2, centre[1] + tall / 2])
            roi = crop_rois(box[None])[0]
            labels = np.reshape(annotation["keypoints"], (17, 3)).astype(np.float64)
            ordered = swap_pairs(labels, [not flag for flag in annotation["left_is_image_left"]])
            ordered[:, :2] = to_crop(ordered[:, :2], roi)
            crops.append(cut(image, roi))
            points.append(ordered)
            heights.append(height / (roi[3] - roi[1]) * CROP[1])
    return np.stack(crops), np.stack(points).astype(np.float32), np.array(heights, np.float32)


def _conv(inputs: int, outputs: int, stride: int = 1, dilation: int = 1) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(inputs, outputs, 3, stride, padding=dilation, dilation=dilation, bias=False),
                         nn.BatchNorm2d(outputs), nn.ReLU(inplace=True))


class CropPoseNet(nn.Module):
    def __init__(self, widths: tuple[int, int, int, int] = (16, 24, 48, 64)) -> None:
        super().__init__()
        a, b, c, d = widths
        self.to_half = nn.Sequential(_conv(3, a, 2), _conv(a, a))
        self.to_quarter = nn.Sequential(_conv(a, b, 2), _conv(b, b))
        self.to_eighth = nn.Sequential(_conv(b, c, 2), _conv(c, c))
        self.sixteenth = nn.Sequential(_conv(c, d, 2), _conv(d, d, dilation=2), _conv(d, d, dilation=2))
        self.up_eighth = _conv(d + c, c)
        self.up_quarter = _conv(c + b, b)
        self.up_half = _conv(b + a, a)
        self.maps = nn.Conv2d(a, len(COCO_KEYPOINTS), 1)

    def forward(self, crops: Tensor) -> Tensor:
        half = self.to_half(crops)
        quarter = self.to_quarter(half)
        eighth = self.to_eighth(quarter)
        deep = self.sixteenth(eighth)
        up = nn.functional.interpolate
        eighth = self.up_eighth(torch.cat([up(deep, scale_factor=2.0), eighth], 1))
        quarter = self.up_quarter(torch.cat([up(eighth, scale_factor=2.0), quarter], 1))
        half = self.up_half(torch.cat([up(quarter, scale_factor=2.0), half], 1))
        return self.maps(half)


def targets(points: np.ndarray) -> tuple[Tensor, Tensor]:
    cells = (points[..., :2] + 0.5) / STRIDE - 0.5
    ys, xs = np.mgrid[0:MAPS[0], 0:MAPS[1]].astype(np.float32)
    maps = np.exp(-((xs - cells[..., 0, None, None]) ** 2 + (ys - cells[..., 1, None, None]) ** 2)
                  / (2 * SIGMA_CELLS ** 2))
    labelled = (points[..., 2] > 0).astype(np.float32)
    return torch.from_numpy(maps.astype(np.float32)), torch.from_numpy(labelled)


def mirrored(crops: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    flipped = points.copy()
    flipped[..., 0] = CROP[0] - 1 - flipped[..., 0]
    return crops[:, :, ::-1], swap_pairs(flipped, np.broadcast_to(SIDE_SWAP, (len(points), len(PAIRS))))


def batch(crops: np.ndarray) -> Tensor:
    return torch.from_numpy(np.ascontiguousarray(crops)).permute(0, 3, 1, 2).float() / 255.0


def read_maps(maps: np.ndarray) -> np.ndarray:
    """Step 3: (N, 17, h, w) maps -> (N, 17, 3) crop pixels and the peak's value."""
    count, channels, height, width = maps.shape
    flat = maps.reshape(count, channels, -1).argmax(-1)
    ys, xs = np.divmod(flat, width)
    n, k = np.meshgrid(np.arange(count), np.arange(channels), indexing="ij")
    peak = maps[n, k, ys, xs]
    dx = np.sign(maps[n, k, ys, np.minimum(xs + 1, width - 1)] - maps[n, k, ys, np.maximum(xs - 1, 0)]) * 0.25
    dy = np.sign(maps[n, k, np.minimum(ys + 1, height - 1), xs] - maps[n, k, np.maximum(ys - 1, 0), xs]) * 0.25
    return np.stack([(xs + dx + 0.5) * STRIDE - 0.5, (ys + dy + 0.5) * STRIDE - 0.5, peak], -1)


def predict(net: CropPoseNet, crops: np.ndarray) -> np.ndarray:
    net.eval()
    with torch.no_grad():
        return np.concatenate([read_maps(net(batch(crops[start:start + 256])).numpy())
                               for start in range(0, len(crops), 256)])


def pckh(read: np.ndarray, points: np.ndarray, heights: np.ndarray) -> dict:
    labelled = points[..., 2] > 0
    near = np.linalg.norm(read[..., :2] - points[..., :2], axis=-1) <= 0.5 * HEAD_FRACTION * heights[:, None]
    per = {name: round(float(near[labelled[:, k], k].mean()), 3) for k, name in enumerate(COCO_KEYPOINTS)}
    return {"overall": round(float(near[labelled].mean()), 4), "per_keypoint": per}


def train(crops: np.ndarray, points: np.ndarray, epochs: int, seed: int, widths: tuple[int, ...]) -> CropPoseNet:
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = CropPoseNet(widths)
    steps = epochs * (len(crops) // BATCH)
    optimiser = torch.optim.AdamW(net.parameters(), LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, LEARNING_RATE, total_steps=steps)
    start, step = time.perf_counter(), 0
    for epoch in range(epochs):
        net.train()
        order = rng.permutation(len(crops))
        for first in range(0, len(crops) - BATCH + 1, BATCH):
            chosen = order[first:first + BATCH]
            looks = np.stack([camera_look(crop, rng) for crop in crops[chosen]])
            labels = points[chosen]
            flip = rng.random(len(chosen)) < 0.5
            if flip.any():
                looks[flip], labels[flip] = mirrored(looks[flip], labels[flip])
            maps, labelled = targets(labels)
            loss = (((net(batch(looks)) - maps) ** 2).mean((2, 3)) * labelled).sum() / labelled.sum().clamp(min=1)
            optimiser.zero_grad()
            (loss * 100).backward()
            optimiser.step()
            schedule.step()
            step += 1
        print(f"epoch {epoch + 1}/{epochs} loss {loss.item():.5f} {time.perf_counter() - start:.0f} s",
              file=sys.stderr, flush=True)
    return net


def main() -> None:
    renders, out = Path(sys.argv[1]), Path(sys.argv[2])
    epochs = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    widths = tuple(map(int, sys.argv[4].split(","))) if len(sys.argv) > 4 else (16, 24, 48, 64)
    torch.set_num_threads(2)
    rng = np.random.default_rng(0)
    train_parts, held_parts = [], []
    for region in read_manifest(renders)["regions"]:
        data = open_region(renders, region)
        train_parts.append(people(data.train, rng, JITTER))
        held_parts.append(people(data.held_out, rng, JITTER))
    crops, points, _ = (np.concatenate(part) for part in zip(*train_parts, strict=True))
    held_crops, held_points, held_heights = (np.concatenate(part) for part in zip(*held_parts, strict=True))
    print(f"{len(crops)} training crops, {len(held_crops)} held out", file=sys.stderr, flush=True)
    start = time.perf_counter()
    net = train(crops, points, epochs, seed=0, widths=widths)
    seconds = time.perf_counter() - start
    torch.save(net.state_dict(), out)
    print(json.dumps({"renders": str(renders), "epochs": epochs, "widths": widths, "train_crops": len(crops),
                      "held_out_crops": len(held_crops), "train_seconds": round(seconds, 1),
                      "held_out_pckh": pckh(predict(net, held_crops), held_points, held_heights)}))


if __name__ == "__main__":
    main()
