"""Labels from geometry (docs/design.md, "Rendering"): masks from coverage, keypoints from the camera model.

Nothing here thresholds image colours. Per person:

* the visible mask: pixels where that person covers at least half the pixel (coverage from the box-filtered
  instance pass; other people and obstacles in front have already taken their share);
* the box: the visible mask's bounding box, in the project's pixel convention (the centre of the top-left pixel
  is (0, 0), so a pixel spans +-0.5 around its index and a mask from column a to b has x = a - 0.5, w = b - a + 1);
* keypoints: anny's 17 COCO keypoints projected through the real camera (distortion included). Visibility
  follows COCO: 0 outside the image, else 1 when the depth pass at the keypoint's pixel shows a surface in front
  of it by more than the keypoint's *burial depth* (how far inside the body the joint lies: its distance to the
  nearest mesh vertex) plus :data:`DEPTH_MARGIN_M` — an obstacle, another person or the body itself — else 2;
* the centre (the point half the stature above the feet) and the foot point (on the ground), projected;
* the amodal box: all of the body's projected vertices, clipped to the image, occluded parts included.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pycocotools import mask as coco_mask

from vc.calibration.camera import Camera

#: Slack (m) on top of a keypoint's burial depth before a surface in front of it counts as occluding.
DEPTH_MARGIN_M = 0.03
#: A pixel belongs to a person's visible mask when the person covers at least this fraction of it.
MASK_COVERAGE = 0.5
#: Every n-th vertex is projected for the amodal box.
AMODAL_VERTEX_STRIDE = 2


def instance_map(coverage: np.ndarray) -> np.ndarray:
    """(H, W, P) coverage -> (H, W) uint8: 0 for no one, k + 1 where person k covers at least half the pixel."""
    if coverage.shape[-1] == 0:
        return np.zeros(coverage.shape[:2], np.uint8)
    best = coverage.argmax(axis=-1)
    covered = np.take_along_axis(coverage, best[..., None], axis=-1)[..., 0] >= MASK_COVERAGE
    return np.where(covered, best + 1, 0).astype(np.uint8)


def mask_box(mask: np.ndarray) -> list[float] | None:
    """COCO [x, y, w, h] of a boolean mask's pixels (project pixel convention), None if the mask is empty."""
    rows, columns = np.nonzero(mask.any(axis=1))[0], np.nonzero(mask.any(axis=0))[0]
    if len(rows) == 0:
        return None
    return [float(columns[0]) - 0.5, float(rows[0]) - 0.5, float(columns[-1] - columns[0] + 1),
            float(rows[-1] - rows[0] + 1)]


def mask_rle(mask: np.ndarray) -> dict:
    """COCO compressed RLE of a boolean mask (what pycocotools reads for ``segmentation``)."""
    encoded = coco_mask.encode(np.asfortranarray(mask.astype(np.uint8)))
    return {"size": [int(n) for n in encoded["size"]], "counts": encoded["counts"].decode("ascii")}


def burial_depths(keypoints: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Distance (m) from each keypoint (K, 3) to the nearest of ``vertices`` (V, 3): how deep inside it lies."""
    squared = ((keypoints[:, None, :].astype(np.float64) - vertices[None, :, :]) ** 2).sum(axis=-1)
    return np.sqrt(squared.min(axis=1))


def keypoint_visibility(camera: Camera, keypoints: np.ndarray, burial: np.ndarray, depth: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions (K, 2) and COCO visibility (K,) of world ``keypoints`` (K, 3) given the depth pass."""
    projection = camera.project(keypoints)
    uv = projection.uv
    inside = projection.ok & camera.is_in_image(np.nan_to_num(uv, nan=-1e9))
    visibility = np.zeros(len(keypoints), np.int64)
    if inside.any():
        columns = np.clip(np.round(uv[inside, 0]).astype(int), 0, camera.width - 1)
        rows = np.clip(np.round(uv[inside, 1]).astype(int), 0, camera.height - 1)
        keypoint_depth = camera.world_to_camera(keypoints[inside])[:, 2]
        occluded = depth[rows, columns] < keypoint_depth - burial[inside] - DEPTH_MARGIN_M
        visibility[inside] = np.where(occluded, 1, 2)
    return np.where(inside[:, None], uv, 0.0), visibility


@dataclass(frozen=True)
class PersonTruth:
    """What the labels of one rendered person are computed from (world coordinates, metres)."""

    vertices: np.ndarray  # (V, 3)
    keypoints: np.ndarray  # (17, 3)
    foot: np.ndarray  # (3,) on the ground
    stature_m: float
    attributes: dict  # position, orientation, phenotype, gait, appearance: carried into the annotation as is


def _projected(camera: Camera, point: np.ndarray) -> list[float] | None:
    projection = camera.project(point[None])
    return [round(float(c), 3) for c in projection.uv[0]] if projection.ok[0] else None


def person_annotation(camera: Camera, truth: PersonTruth, mask: np.ndarray, depth: np.ndarray) -> dict | None:
    """The COCO annotation fields of one person (no ids), or None when no pixel of the person is visible."""
    box = mask_box(mask)
    if box is None:
        return None
    uv, visibility = keypoint_visibility(camera, truth.keypoints, burial_depths(truth.keypoints, truth.vertices),
                                         depth)
    keypoints = np.concatenate([np.round(uv, 3), visibility[:, None]], axis=1)
    body = camera.project(truth.vertices[::AMODAL_VERTEX_STRIDE].astype(np.float64))
    corners = body.uv[body.ok]
    low = np.maximum(corners.min(axis=0), -0.5)
    high = np.minimum(corners.max(axis=0), [camera.width - 0.5, camera.height - 0.5])
    centre = truth.foot + np.array([0.0, 0.0, truth.stature_m / 2])
    return {
        "bbox": box,
        "area": int(mask.sum()),
        "iscrowd": 0,
        "num_keypoints": int((visibility > 0).sum()),
        "keypoints": [float(value) if i % 3 < 2 else int(value) for i, value in enumerate(keypoints.ravel())],
        "segmentation": mask_rle(mask),
        "center": _projected(camera, centre),
        "foot": _projected(camera, truth.foot),
        "amodal_bbox": [round(float(low[0]), 3), round(float(low[1]), 3), round(float(high[0] - low[0]), 3),
                        round(float(high[1] - low[1]), 3)],
        "attributes": truth.attributes,
    }
