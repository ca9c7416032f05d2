"""Reading a ``vc-render`` dataset for training: one region's shards, checked, split, and encoded as targets.

Held-out data is whole shards (the last ``held_out_fraction`` of them, at least one when there are two or more),
so that evaluation never sees a training sample and the split is the same on every machine.

Augmentation only adds what the renderer cannot vary yet (DESIGN.md): exposure and contrast (until photometric
calibration estimates them) and sensor noise (not simulated). Geometry is never augmented: a flipped or rescaled
sample would no longer be the scene's own perspective.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch.utils.data import Dataset

from vc.errors import InputError
from vc.io import read_image
from vc.model.codec import CodecConfig, encode
from vc.render.dataset import ANNOTATIONS, MANIFEST


@dataclass(frozen=True)
class Sample:
    image_path: Path
    mask_path: Path
    annotations: list[dict]


@dataclass(frozen=True)
class RegionData:
    """One region of a dataset: its entry in the manifest and its samples, split into train and held-out."""

    name: str
    manifest: dict
    region: dict
    train: list[Sample]
    held_out: list[Sample]

    @property
    def input_size(self) -> tuple[int, int]:
        width, height = self.region["input_size"]
        return width, height


def read_manifest(root: Path) -> dict:
    path = root / MANIFEST
    if not path.is_file():
        raise InputError(path, "", "not a vc-render dataset (no manifest.json)")
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise InputError(path, "", f"cannot read the dataset manifest ({error})") from None


def _shard_samples(shard: Path) -> list[Sample]:
    path = shard / ANNOTATIONS
    try:
        document = json.loads(path.read_text())
        images = document["images"]
        by_image: dict[int, list[dict]] = {image["id"]: [] for image in images}
        for annotation in document["annotations"]:
            by_image[annotation["image_id"]].append(annotation)
    except FileNotFoundError:
        raise InputError(path, "", "shard has no annotations (an interrupted render? run vc-render again)") from None
    except (OSError, json.JSONDecodeError, KeyError, TypeError) as error:
        raise InputError(path, "", f"corrupt shard annotations ({type(error).__name__}: {error})") from None
    if not images:
        raise InputError(path, "images", "shard holds no samples")
    samples = []
    for image in images:
        sample = Sample(shard / image["file_name"], shard / image["mask_file"], by_image[image["id"]])
        for file in (sample.image_path, sample.mask_path):
            if not file.is_file():
                raise InputError(file, "", "missing from its shard")
        samples.append(sample)
    return samples


def open_region(root: Path, region: str, held_out_fraction: float = 0.1) -> RegionData:
    """Check and index one region of the dataset at ``root``."""
    manifest = read_manifest(root)
    regions = manifest.get("regions", {})
    if region not in regions:
        raise InputError(root / MANIFEST, "regions", f"region {region!r} is not in this dataset (it has "
                                                     f"{', '.join(regions) or 'none'})")
    shards = sorted(path for path in (root / region).glob("shard-*") if path.is_dir() and "." not in path.name)
    if not shards:
        raise InputError(root / region, "", "no finished shards for this region")
    held = max(1, round(len(shards) * held_out_fraction)) if len(shards) > 1 else 0
    train = [s for shard in shards[:len(shards) - held] for s in _shard_samples(shard)]
    held_out = [s for shard in shards[len(shards) - held:] for s in _shard_samples(shard)]
    return RegionData(region, manifest, regions[region], train, held_out)


@dataclass(frozen=True)
class Augmentation:
    """Photometric jitter for what the renderer does not vary (see the module docstring)."""

    exposure: float = 0.25  # log2 range of the exposure multiplier (+-)
    contrast: float = 0.15  # +- fraction
    noise: float = 0.02  # max standard deviation of additive noise (in [0, 1] units)

    def apply(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        gain = 2.0 ** rng.uniform(-self.exposure, self.exposure)
        contrast = 1.0 + rng.uniform(-self.contrast, self.contrast)
        mean = image.mean()
        image = (image - mean) * contrast + mean
        image = image * gain + rng.normal(0.0, rng.uniform(0.0, self.noise), image.shape)
        return np.clip(image, 0.0, 1.0).astype(np.float32)


class RegionDataset(Dataset):
    """(image (3, H, W) float in [0, 1], heat maps (19, H/s, W/s)) pairs of one region's samples.

    With ``augmentation``, each epoch sees different jitter, still a pure function of (seed, epoch, index).
    """

    def __init__(self, samples: list[Sample], codec: CodecConfig, augmentation: Augmentation | None = None,
                 seed: int = 0) -> None:
        self.samples, self.codec, self.augmentation, self.seed = samples, codec, augmentation, seed
        self.epoch = 0

    def __len__(self) -> int:
        return len(self.samples)

    def __getitem__(self, index: int) -> tuple[torch.Tensor, torch.Tensor]:
        sample = self.samples[index]
        image = read_image(sample.image_path).astype(np.float32) / 255.0
        instances = read_image(sample.mask_path)[..., 0]
        targets = encode(sample.annotations, instances, self.codec)
        if self.augmentation is not None:
            image = self.augmentation.apply(image, np.random.default_rng([self.seed, self.epoch, index]))
        return torch.from_numpy(np.ascontiguousarray(image.transpose(2, 0, 1))), torch.from_numpy(targets)
