"""The training stream: one region's samples (read by :func:`vc.render.dataset.open_region`) cut into windows,
jittered and encoded as targets, as torch tensors.

Training draws windows of the region input (:class:`CropPolicy`); each window's composite is varied over the
camera's life (:mod:`vc.model.camera_range`: exposure, white balance, night IR, gain noise, blur, compression), then
jittered slightly (:class:`Augmentation`). Geometry is never augmented: a flipped or rescaled sample would no
longer be the scene's own perspective.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from torch.utils.data import Dataset

from vc.model.camera_range import CameraLife
from vc.model.codec import CodecConfig, encode
from vc.render.dataset import Sample, read_sample


@dataclass(frozen=True)
class Augmentation:
    """A slight photometric jitter of every window, after the camera range (see the module docstring)."""

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    exposure: float = 0.25  # log2 range of the exposure multiplier (+-)
    contrast: float = 0.15  # +- fraction
    noise: float = 0.02  # max standard deviation of additive noise (in [0, 1] units)

    def apply(self, image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``image`` (float32, changed in place) jittered: ``clip(((image - mean) * contrast + mean) * gain +
        noise, 0, 1)``, one operation at a time in place, which gives the same float32 values without the
        temporaries (the loader shares the cores with the training step: its time is the step's)."""
        gain = 2.0 ** rng.uniform(-self.exposure, self.exposure)
        contrast = 1.0 + rng.uniform(-self.contrast, self.contrast)
        mean = image.mean()
        image -= mean
        image *= contrast
        image += mean
        noise = rng.standard_normal(image.shape, dtype=np.float32)
        noise *= np.float32(rng.uniform(0.0, self.noise))
        image *= np.float32(gain)
        image += noise
        return np.clip(image, 0.0, 1.0, out=image)


def shifted(annotation: dict, dx: float, dy: float) -> dict:
    """The fields the codec reads, moved by (dx, dy) input pixels (a window's origin)."""
    keypoints = np.reshape(annotation["keypoints"], (-1, 3)) + [dx, dy, 0.0]
    centre = annotation.get("center")
    return {"center": None if centre is None else [centre[0] + dx, centre[1] + dy],
            "keypoints": keypoints.ravel().tolist(), "amodal_bbox": annotation["amodal_bbox"],
            "left_is_image_left": annotation.get("left_is_image_left"), "instance_id": annotation.get("instance_id")}


@dataclass(frozen=True)
class CropPolicy:
    """Training windows cut from a region's input: the network is fully convolutional, so it learns from windows
    and runs on the whole input; windows keep every pixel where it was (no rescaling: the scene's perspective
    stays), and most are centred near a person so that steps are not spent on empty ground."""

    #: Read strictly when pydantic validates a stored training config (:func:`vc.model.trainer.read_train_config`).
    __pydantic_config__ = {"extra": "forbid"}

    size: tuple[int, int] = (256, 256)  # width, height; clipped to the region's input
    near_person: float = 0.8  # fraction of windows centred on a person (jittered by a quarter window)

    def window(self, annotations: list[dict], input_size: tuple[int, int], stride: int,
               rng: np.random.Generator) -> tuple[int, int, int, int]:
        """(x0, y0, width, height) in input pixels, on the stride grid so that targets crop cell for cell."""
        (width, height), (crop_width, crop_height) = input_size, self.size
        crop_width, crop_height = min(crop_width, width), min(crop_height, height)
        centres = [a["center"] for a in annotations if a.get("center") is not None]
        if centres and rng.random() < self.near_person:
            x, y = centres[rng.integers(len(centres))]
            x0 = x - crop_width / 2 + rng.uniform(-0.25, 0.25) * crop_width
            y0 = y - crop_height / 2 + rng.uniform(-0.25, 0.25) * crop_height
        else:
            x0, y0 = rng.uniform(0, width - crop_width), rng.uniform(0, height - crop_height)
        x0 = int(np.clip(round(x0 / stride) * stride, 0, width - crop_width))
        y0 = int(np.clip(round(y0 / stride) * stride, 0, height - crop_height))
        return x0, y0, crop_width, crop_height


class TrainingStream(Dataset):
    """Training items indexed by draw number: draw ``k`` is sample ``permutation(epoch)[k % n]`` of epoch
    ``k // n``, cropped and jittered by a generator seeded with (seed, k).

    ``camera_life`` varies the windows over the camera's range (None: they keep the scene's look).

    Every item is a pure function of (seed, k), so a run resumed at step s (draws from s * batch size) sees the
    same data as one that never stopped, and data-loader workers cannot change the result. Decoded samples are
    kept in memory up to ``cache_bytes`` (PNG decoding costs more than the rest of an item; a run sees each
    sample many times).
    """

    def __init__(self, samples: list[Sample], codec: CodecConfig, input_size: tuple[int, int],
                 crop: CropPolicy | None = CropPolicy(), augmentation: Augmentation | None = Augmentation(),
                 seed: int = 0, cache_bytes: int = 4 << 30, camera_life: CameraLife | None = None) -> None:
        if not samples:
            raise ValueError("no training samples")
        self.samples, self.codec, self.input_size = samples, codec, input_size
        self.crop, self.augmentation, self.seed, self.camera_life = crop, augmentation, seed, camera_life
        self.cache_bytes, self._cache, self._cached_bytes = cache_bytes, {}, 0
        self._permutation: tuple[int, np.ndarray] | None = None  # (epoch, its sample order): drawn once an epoch

    def __len__(self) -> int:
        return len(self.samples)

    def sample_index(self, draw: int) -> int:
        epoch, position = divmod(draw, len(self.samples))
        if self._permutation is None or self._permutation[0] != epoch:
            self._permutation = epoch, np.random.default_rng([self.seed, epoch]).permutation(len(self.samples))
        return int(self._permutation[1][position])

    def _decoded(self, index: int) -> tuple[np.ndarray, np.ndarray]:
        if index in self._cache:
            return self._cache[index]
        image, instances = read_sample(self.samples[index])
        if self._cached_bytes + image.nbytes + instances.nbytes <= self.cache_bytes:
            self._cache[index] = image, instances
            self._cached_bytes += image.nbytes + instances.nbytes
        return image, instances

    def __getitem__(self, draw: int) -> tuple[torch.Tensor, torch.Tensor]:
        index = self.sample_index(draw)
        annotations = self.samples[index].annotations
        image, instances = self._decoded(index)
        rng = np.random.default_rng([self.seed, 1 << 32, draw])  # apart from the permutations' streams
        if self.crop is not None:
            x0, y0, width, height = self.crop.window(annotations, self.input_size, self.codec.stride, rng)
            image, instances = image[y0:y0 + height, x0:x0 + width], instances[y0:y0 + height, x0:x0 + width]
            annotations = [shifted(annotation, -x0, -y0) for annotation in annotations]
        targets = encode(annotations, instances, self.codec)
        if self.camera_life is not None:
            image = self.camera_life.apply(image, rng)
        image = image.astype(np.float32) / 255.0
        if self.augmentation is not None:
            image = self.augmentation.apply(image, rng)
        return torch.from_numpy(np.ascontiguousarray(image.transpose(2, 0, 1))), torch.from_numpy(targets)
