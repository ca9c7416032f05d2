"""The dataset on disk: ``<out>/<region>/shard-NNNNN/{images,masks,annotations.json}`` plus ``manifest.json``.

* ``images/<index>.png``: the sample as the camera would encode it (8-bit, the scene's response).
* ``masks/<index>.png``: 8-bit instance map, 0 for nobody and k for the annotation whose ``instance_id`` is k.
* ``annotations.json``: COCO keypoints format (pycocotools reads it) for the shard's samples. Image ids are the
  sample indices; annotation ids are ``index * ANNOTATION_ID_STRIDE + instance_id``, unique in the region.
  Coordinates follow the project's pixel convention (the centre of the top-left pixel is (0, 0)); beyond COCO's
  fields each annotation has ``center``, ``foot``, ``amodal_bbox``, ``instance_id`` and the person's 3-D
  ``attributes`` (see :mod:`vc.render.labels`).

* ``SHA256SUMS``: the SHA-256 of every other file of the shard, in ``sha256sum`` format (``sha256sum -c``
  checks it by hand). A damaged shard is found by it: ``vc-render`` re-makes it, readers refuse it.

A shard is written into ``shard-NNNNN.partial/`` and renamed into place when complete, so a finished shard is
never rewritten and a crash leaves at most one partial folder, which the next run discards and redoes. Shards
depend only on the manifest's settings, so a resumed run yields the same bytes as an uninterrupted one.

The reader is here too, torch-free (training, export and the self-test use it): :func:`open_region` checks and
indexes one region and splits it. Held-out data is whole shards (the last ``held_out_fraction`` of them, at least
one; a region needs two shards or more), so that evaluation never sees a training sample and the split is the
same on every machine.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from vc.calibration.camera import Camera, camera_from_dict
from vc.deploy.heatmaps import PAIRS
from vc.errors import InputError
from vc.io import FAST_PNG_COMPRESSION, atomic_path, read_image, write_image, write_json
from vc.keypoints import COCO_KEYPOINTS, COCO_SKELETON_1BASED

if TYPE_CHECKING:
    from vc.render.synthesis import RenderedSample

#: 2: the manifest records the render plan (light, camera measurements, effects with their parameters).
#: 3: every shard carries its checksums (:data:`CHECKSUMS`).
FORMAT_VERSION = 3
#: Dataset formats this version reads: 1 (before the render plan was recorded) and 2 differ from 3 only by what
#: they lack; their shards are read unchecked.
READABLE_FORMAT_VERSIONS = (1, 2, 3)
MANIFEST = "manifest.json"
ANNOTATIONS = "annotations.json"
CHECKSUMS = "SHA256SUMS"
#: Annotation ids are sample index * this + instance id (a sample never holds this many people).
ANNOTATION_ID_STRIDE = 100
PERSON_CATEGORY = {
    "id": 1,
    "name": "person",
    "supercategory": "person",
    "keypoints": list(COCO_KEYPOINTS),
    "skeleton": [list(pair) for pair in COCO_SKELETON_1BASED],
}


@dataclass(frozen=True)
class Shard:
    region: str
    number: int
    start: int  # first sample index
    stop: int  # one past the last

    @property
    def name(self) -> str:
        return f"shard-{self.number:05d}"

    def folder(self, root: Path) -> Path:
        return root / self.region / self.name


def plan_shards(region: str, samples: int, shard_size: int) -> list[Shard]:
    return [Shard(region, number, start, min(start + shard_size, samples))
            for number, start in enumerate(range(0, samples, shard_size))]


def is_complete(root: Path, shard: Shard) -> bool:
    """A shard folder exists under its final name only once everything in it is written."""
    return (shard.folder(root) / ANNOTATIONS).is_file()


def _sha256(path: Path) -> str:
    with path.open("rb") as file:
        return hashlib.file_digest(file, "sha256").hexdigest()


def write_checksums(folder: Path) -> None:
    """Record the SHA-256 of every file under ``folder`` in ``folder/SHA256SUMS`` (sorted, ``sha256sum`` format)."""
    files = sorted(path for path in folder.rglob("*") if path.is_file() and path.name != CHECKSUMS)
    lines = [f"{_sha256(path)}  {path.relative_to(folder).as_posix()}\n" for path in files]
    with atomic_path(folder / CHECKSUMS) as temporary:
        temporary.write_text("".join(lines))


def damaged_files(folder: Path) -> list[str]:
    """The files of ``folder`` that differ from its ``SHA256SUMS`` (missing ones and the list itself included,
    when it cannot be read); empty for an intact folder."""
    try:
        listed = dict(reversed(line.split("  ", 1)) for line in (folder / CHECKSUMS).read_text().splitlines())
    except (OSError, UnicodeDecodeError, ValueError):
        return [CHECKSUMS]
    present = {path.relative_to(folder).as_posix() for path in folder.rglob("*")
               if path.is_file() and path.name != CHECKSUMS}
    damaged = sorted(present - set(listed))  # a file nobody wrote
    for name, digest in sorted(listed.items()):
        if name not in present or _sha256(folder / name) != digest:
            damaged.append(name)
    return damaged


def has_checksums(manifest: dict) -> bool:
    """Whether a dataset's shards carry checksums (format 3 on)."""
    return manifest.get("format_version", 0) >= 3


def image_name(index: int) -> str:
    return f"{index:06d}.png"


@dataclass(frozen=True)
class WrittenSample:
    """What the annotation file needs of a sample once its pixels are on disk."""

    index: int
    width: int
    height: int
    annotations: list[dict]


def coco_document(info: dict, samples: Iterable[WrittenSample]) -> dict:
    images, annotations = [], []
    for sample in samples:
        images.append({"id": sample.index, "file_name": f"images/{image_name(sample.index)}",
                       "mask_file": f"masks/{image_name(sample.index)}", "width": sample.width,
                       "height": sample.height})
        for annotation in sample.annotations:
            annotations.append({"id": sample.index * ANNOTATION_ID_STRIDE + annotation["instance_id"],
                                "image_id": sample.index, "category_id": PERSON_CATEGORY["id"], **annotation})
    return {"info": info, "images": images, "annotations": annotations, "categories": [PERSON_CATEGORY]}


def write_shard(root: Path, shard: Shard, samples: Iterable[RenderedSample], info: dict) -> dict:
    """Write a shard atomically (see the module docstring); returns its counts."""
    final = shard.folder(root)
    partial = final.with_name(final.name + ".partial")
    shutil.rmtree(partial, ignore_errors=True)
    (partial / "images").mkdir(parents=True)
    (partial / "masks").mkdir()
    written = []
    # PNG encoding overlaps with rendering the next sample: zlib releases the GIL.
    with ThreadPoolExecutor(max_workers=1) as writer:
        pending = []
        for sample in samples:
            pending.append(writer.submit(write_image, partial / "images" / image_name(sample.index), sample.image,
                                         FAST_PNG_COMPRESSION))
            pending.append(writer.submit(write_image, partial / "masks" / image_name(sample.index),
                                         sample.instances[..., None], FAST_PNG_COMPRESSION))
            written.append(WrittenSample(sample.index, sample.image.shape[1], sample.image.shape[0],
                                         sample.annotations))
        for future in pending:
            future.result()
    document = coco_document({**info, "shard": shard.name}, written)
    write_json(partial / ANNOTATIONS, document)
    write_checksums(partial)
    os.replace(partial, final)
    return {"samples": len(written), "people": len(document["annotations"])}


def shard_counts(root: Path, shard: Shard) -> dict:
    document = json.loads((shard.folder(root) / ANNOTATIONS).read_text())
    return {"samples": len(document["images"]), "people": len(document["annotations"])}


def read_manifest(root: Path, missing_ok: bool = False) -> dict | None:
    """The dataset manifest of ``root``, in a format this version reads (:data:`READABLE_FORMAT_VERSIONS`); None
    when there is none and ``missing_ok`` (a render about to start), else an InputError."""
    path = Path(root) / MANIFEST
    if not path.is_file():
        if missing_ok:
            return None
        raise InputError(path, "", "not a vc-render dataset (no manifest.json)")
    try:
        manifest = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise InputError(path, "", f"cannot read the dataset manifest ({error})") from None
    if not isinstance(manifest, dict) or manifest.get("format_version") not in READABLE_FORMAT_VERSIONS:
        version = manifest.get("format_version") if isinstance(manifest, dict) else None
        raise InputError(path, "format_version", f"unsupported dataset format {version!r} (this version reads "
                                                 f"{', '.join(map(str, READABLE_FORMAT_VERSIONS))})")
    return manifest


def plan_entries(plan: dict) -> dict:
    """The manifest's entries for a render plan (:meth:`vc.render.plan.RenderPlan.to_dict`): what the pixels were
    rendered with, and nothing that varies from run to run (the effects' measured costs go to the render
    summary), so a resumed render writes the same manifest."""
    effects = [{key: value for key, value in effect.items() if key != "ms_per_sample"} for effect in plan["effects"]]
    return {"response": plan["response"], "lighting": plan["lighting"],
            "camera_measurements": plan["camera_measurements"], "effects": effects}


def _rendered_with(manifest: dict) -> dict:
    """What a dataset's pixels depend on beyond its settings: the camera response, the light and the parameters of
    each effect that is on (not the measured costs, which vary from run to run; an effect that is off, or that the
    version which rendered it did not know, changed no pixel)."""
    return {"response": (manifest.get("response") or {}).get("name"),
            "illumination": manifest.get("lighting", {}).get("illumination"),
            "effects": [(e.get("name"), e.get("parameters")) for e in manifest.get("effects", []) if e.get("on")]}


def check_manifest(root: Path, existing: dict | None, manifest: dict) -> None:
    """Refuse to add to a dataset rendered with other settings: its shards would not belong together."""
    if existing is None:
        return
    path = root / MANIFEST
    for key in ("format_version", "scene_hash", "settings"):
        if existing.get(key) != manifest.get(key):
            raise InputError(path, key, "the output folder holds a dataset rendered with different "
                                        f"{key.replace('_', ' ')}; choose another folder or remove it")
    if _rendered_with(existing) != _rendered_with(manifest):
        raise InputError(path, "lighting", "the output folder holds a dataset rendered under other light or other "
                                           "camera effects; choose another folder or remove it")
    for name, region in manifest["regions"].items():
        before = existing.get("regions", {}).get(name)
        if before is not None and before.get("samples") != region["samples"]:
            raise InputError(path, f"regions.{name}.samples",
                             f"region {name} was rendered with {before.get('samples')} samples, not "
                             f"{region['samples']}; use the same --samples or another folder")


def write_manifest(root: Path, manifest: dict, existing: dict | None = None) -> None:
    """Write the manifest, keeping regions an earlier run rendered and this one did not touch."""
    regions = {**(existing or {}).get("regions", {}), **manifest["regions"]}
    write_json(root / MANIFEST, {**manifest, "regions": dict(sorted(regions.items()))})


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


def _shard_samples(shard: Path, camera: Camera, checked: bool) -> list[Sample]:
    if checked and (damaged := damaged_files(shard)):
        raise InputError(shard / damaged[0], "", f"does not match the shard's {CHECKSUMS} ({len(damaged)} damaged "
                                                 f"file(s) in {shard.name}); run vc-render on the dataset again to "
                                                 f"re-make the shard")
    path = shard / ANNOTATIONS
    try:
        document = json.loads(path.read_text())
        images = document["images"]
        by_image: dict[int, list[dict]] = {image["id"]: [] for image in images}
        for annotation in document["annotations"]:
            annotation["left_is_image_left"] = _left_is_image_left(annotation, camera)
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


def _left_is_image_left(annotation: dict, camera: Camera) -> list[bool]:
    """Per keypoint pair, whether the person's left member lies further left in the region's image than the right
    one: the codec's image order (:mod:`vc.deploy.heatmaps`). From the 3-D keypoints that vc-render records, so
    that it is defined for keypoints outside the image too; annotations without them are ordered by their
    labelled pixels (a pair with an unlabelled member keeps its anatomical order)."""
    keypoints_m = annotation.get("attributes", {}).get("keypoints_m")
    if keypoints_m is not None:
        x = camera.project(np.asarray(keypoints_m, np.float64)).uv[:, 0]
        return [bool(x[left] <= x[right]) for left, right in PAIRS]
    labels = np.reshape(annotation["keypoints"], (-1, 3))
    return [bool(labels[left, 2] == 0 or labels[right, 2] == 0 or labels[left, 0] <= labels[right, 0])
            for left, right in PAIRS]


#: Finished shards a region needs to be trained: training holds whole shards out for evaluation.
MIN_SHARDS = 2


def open_region(root: Path, region: str, held_out_fraction: float = 0.1) -> RegionData:
    """Check and index one region of the dataset at ``root``: every shard against its checksums (a damaged one is
    an InputError naming the file, never read), then its annotations."""
    manifest = read_manifest(root)
    regions = manifest.get("regions", {})
    if region not in regions:
        raise InputError(root / MANIFEST, "regions", f"region {region!r} is not in this dataset (it has "
                                                     f"{', '.join(regions) or 'none'})")
    shards = sorted(path for path in (root / region).glob("shard-*") if path.is_dir() and "." not in path.name)
    if not shards:
        raise InputError(root / region, "", "no finished shards for this region")
    if len(shards) < MIN_SHARDS:
        raise InputError(root / region, "", f"{len(shards)} finished shard; training holds whole shards out for "
                                            f"evaluation, so it needs at least {MIN_SHARDS} (render more samples or "
                                            "a smaller --shard-size)")
    held = max(1, round(len(shards) * held_out_fraction))
    camera = camera_from_dict(regions[region]["camera"])
    checked = has_checksums(manifest)
    train = [s for shard in shards[:len(shards) - held] for s in _shard_samples(shard, camera, checked)]
    held_out = [s for shard in shards[len(shards) - held:] for s in _shard_samples(shard, camera, checked)]
    return RegionData(region, manifest, regions[region], train, held_out)


def read_sample(sample: Sample) -> tuple[np.ndarray, np.ndarray]:
    """A sample's image (H, W, 3) uint8 and instance map (H, W) uint8."""
    return read_image(sample.image_path), read_image(sample.mask_path)[..., 0]
