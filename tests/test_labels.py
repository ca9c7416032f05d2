"""Labels from geometry: instance maps, boxes in the pixel convention, RLE, keypoint visibility from depth."""

from __future__ import annotations

import numpy as np
import pytest
from pycocotools import mask as coco_mask

from vc.calibration.camera import Camera, look_at
from vc.render.labels import burial_depths, instance_map, keypoint_visibility, mask_box, mask_rle

CAMERA = Camera(64, 48, np.array([[60.0, 0.0, 31.5], [0.0, 60.0, 23.5], [0.0, 0.0, 1.0]]),
                *look_at([0.0, -4.0, 1.0], [0.0, 0.0, 1.0]))


def test_instance_map_gives_each_pixel_to_the_person_covering_at_least_half_of_it() -> None:
    coverage = np.zeros((2, 3, 2), np.float32)
    coverage[0, 0] = [0.6, 0.3]  # person 1
    coverage[0, 1] = [0.2, 0.7]  # person 2
    coverage[0, 2] = [0.4, 0.4]  # nobody has half
    coverage[1, 0] = [0.5, 0.0]  # exactly half counts
    np.testing.assert_array_equal(instance_map(coverage), [[1, 2, 0], [1, 0, 0]])
    assert instance_map(np.zeros((2, 3, 0), np.float32)).shape == (2, 3)


def test_mask_box_uses_the_pixel_centre_convention() -> None:
    mask = np.zeros((10, 12), bool)
    mask[2:5, 3:9] = True  # rows 2-4, columns 3-8
    assert mask_box(mask) == [2.5, 1.5, 6.0, 3.0]
    assert mask_box(np.zeros((4, 4), bool)) is None


def test_rle_round_trips_through_pycocotools() -> None:
    rng = np.random.default_rng(0)
    mask = rng.random((37, 23)) > 0.6
    rle = mask_rle(mask)
    assert isinstance(rle["counts"], str) and rle["size"] == [37, 23]
    decoded = coco_mask.decode({"size": rle["size"], "counts": rle["counts"].encode()})
    np.testing.assert_array_equal(decoded.astype(bool), mask)
    assert coco_mask.area({"size": rle["size"], "counts": rle["counts"].encode()}) == mask.sum()


def test_burial_depth_is_the_distance_to_the_nearest_vertex() -> None:
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    np.testing.assert_allclose(burial_depths(np.array([[0.2, 0.0, 0.0], [1.0, 0.3, 0.0]]), vertices), [0.2, 0.3])


@pytest.mark.parametrize(("surface_offset", "expected"), [
    (np.inf, 2),   # nothing in front: visible
    (-0.05, 2),    # the body's own surface, closer than burial + margin: still visible
    (-0.5, 1),     # something half a metre in front: occluded
])
def test_keypoint_visibility_comes_from_the_depth_pass(surface_offset: float, expected: int) -> None:
    keypoint = np.array([[0.1, 0.2, 1.1]])
    z = CAMERA.world_to_camera(keypoint)[0, 2]
    depth = np.full((CAMERA.height, CAMERA.width), np.inf, np.float32)
    u, v = np.round(CAMERA.project(keypoint).uv[0]).astype(int)
    depth[v, u] = z + surface_offset
    uv, visibility = keypoint_visibility(CAMERA, keypoint, np.array([0.04]), depth)
    assert visibility[0] == expected
    np.testing.assert_allclose(uv[0], CAMERA.project(keypoint).uv[0])


def test_keypoints_outside_the_image_or_behind_the_camera_are_unlabelled() -> None:
    keypoints = np.array([[5.0, 0.0, 1.0], [0.0, -6.0, 1.0]])  # far to the side; behind the camera
    depth = np.full((CAMERA.height, CAMERA.width), np.inf, np.float32)
    uv, visibility = keypoint_visibility(CAMERA, keypoints, np.zeros(2), depth)
    np.testing.assert_array_equal(visibility, [0, 0])
    np.testing.assert_array_equal(uv, np.zeros((2, 2)))
