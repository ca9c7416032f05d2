"""A small vc-render dataset without rendering: flat "people" (a dark box with a light head) placed where the
region camera says a person of that height would stand, labelled with the fields the trainer reads, written by
the real shard writer. Fast enough for training tests; geometrically consistent with the decoder's boxes."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vc.calibration.camera import Camera, look_at
from vc.deploy.decode import UPRIGHT_OFFSETS
from vc.render import dataset
from vc.render.labels import mask_box
from vc.render.synthesis import RenderedSample

INPUT_SIZE = (128, 64)
SCENE_HASH = "f" * 64


def region_camera() -> Camera:
    R, t = look_at([0.0, -10.0, 5.0], [0.0, 6.0, 0.0])
    K = np.array([[260.0, 0.0, 63.5], [0.0, 260.0, 31.5], [0.0, 0.0, 1.0]])
    return Camera(*INPUT_SIZE, K=K, R=R, t=t)


def _person(camera: Camera, rng: np.random.Generator, instance_id: int, image: np.ndarray,
            instances: np.ndarray) -> dict | None:
    height_m = float(rng.uniform(1.6, 1.9))
    centre = np.array([rng.uniform(4, INPUT_SIZE[0] - 4), rng.uniform(14, INPUT_SIZE[1] - 14)])
    height = float(camera.person_height_at_centres(centre, height_m))
    if not np.isfinite(height):
        return None
    rows, columns = np.indices(instances.shape)
    body = (np.abs(columns - centre[0]) <= 0.14 * height) & (np.abs(rows - centre[1]) <= 0.5 * height) \
        & (instances == 0)
    head = body & (rows < centre[1] - 0.36 * height)
    if not body.any():
        return None
    image[body] = rng.integers(20, 90, 3)
    image[head] = (220, 180, 150)
    instances[body] = instance_id
    keypoints = np.zeros((17, 3))
    keypoints[:, 0] = centre[0] + np.tile([-1, 1], 9)[:17] * 0.08 * height
    keypoints[:, 1] = centre[1] + UPRIGHT_OFFSETS * height
    keypoints[:, 2] = 2
    return {"instance_id": instance_id, "bbox": mask_box(body), "area": int(body.sum()), "iscrowd": 0,
            "num_keypoints": 17, "keypoints": keypoints.ravel().round(3).tolist(), "center": centre.tolist(),
            "foot": [centre[0], centre[1] + height / 2],
            "amodal_bbox": [centre[0] - 0.14 * height, centre[1] - 0.5 * height, 0.28 * height, height],
            "attributes": {"height_m": height_m}}


def sample(camera: Camera, index: int, seed: int = 0) -> RenderedSample:
    rng = np.random.default_rng([seed, index])
    image = np.empty((INPUT_SIZE[1], INPUT_SIZE[0], 3), np.uint8)
    image[:] = np.linspace(110, 160, INPUT_SIZE[0])[None, :, None].astype(np.uint8)
    instances = np.zeros(image.shape[:2], np.uint8)
    annotations = []
    for instance_id in range(1, int(rng.integers(0, 4)) + 1):
        person = _person(camera, rng, instance_id, image, instances)
        if person is not None:
            annotations.append(person)
    return RenderedSample(index, image, instances, annotations, np.zeros(image.shape[:2], np.float32))


def write_dataset(root: Path, samples: int = 24, shard_size: int = 8, region: str = "r0", scene_hash: str = SCENE_HASH,
                  seed: int = 0) -> Path:
    camera = region_camera()
    for number, start in enumerate(range(0, samples, shard_size)):
        shard = dataset.Shard(region, number, start, min(start + shard_size, samples))
        dataset.write_shard(root, shard, (sample(camera, i, seed) for i in range(shard.start, shard.stop)), {})
    # The frame is the region's input itself (crop window = whole frame, scale 1); the region owns its left 3/4.
    width, height = INPUT_SIZE
    owned = {"type": "Polygon", "coordinates": [[[-0.5, -0.5], [0.75 * width, -0.5], [0.75 * width, height],
                                                 [-0.5, height], [-0.5, -0.5]]]}
    entry = {"name": region, "input_size": list(INPUT_SIZE), "crop_window": [0, 0, width, height],
             "camera": camera.to_dict(), "ground_polygon": {"type": "Polygon", "coordinates": []},
             "owned_image_area": owned}
    manifest = {"format_version": dataset.FORMAT_VERSION, "scene": "flat", "scene_hash": scene_hash,
                "camera": camera.to_dict(), "settings": {"seed": seed}, "regions": {region: entry}}
    dataset.write_manifest(root, manifest)
    return root
