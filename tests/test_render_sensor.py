"""Mitsuba sensors image exactly like the calibrated camera (docs/design.md, "Conventions": the half-pixel shift).

A small emissive sphere rendered at a known 3-D point must appear where ``Camera.project`` puts that point, to
within 0.1 px: directly for an ideal pinhole, and through the warp for a camera with anisotropic focal lengths,
skew and lens distortion. The warp itself is checked on a synthetic coordinate image, without Mitsuba. The
layout scene is checked through the same sensors: paving where the walkable polygon projects, obstacles and
walls inside their projected hulls (size and yaw conventions), and byte-identical renders for one seed.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from vc.calibration.camera import Camera, look_at
from vc.calibration.distortion import BrownConrady, TsaiRadial
from vc.render.background import render_background
from vc.render.layout_scene import layout_scene_dict
from vc.render.mitsuba_setup import mitsuba
from vc.render.relight import explicit_illumination
from vc.render.sensor import film_position, ideal_view, is_ideal, perspective_sensor
from vc.scenes.layout import Box, Cylinder, Layout, Wall, densify_segments
from vc.scenes.schema import Lighting

WIDTH, HEIGHT = 160, 120
#: World points seen by the test cameras: near the centre, off to a side, and close to a corner.
POINTS = np.array([[0.0, 0.0, 0.5], [0.9, 0.4, 1.2], [-1.6, 0.2, 0.1], [1.55, -0.6, 1.75]])
#: About 5 px across at 5 m. Smaller spheres are undersampled: bilinear resampling in the warp then moves the
#: centroid by an amount that depends on sub-pixel phase (measured up to 0.06 px at 3.5 px, 0.09 px at 2 px).
SPHERE_RADIUS_M = 0.08
CENTROID_TOLERANCE_PX = 0.1

#: The default sun and sky of an explicit ``lighting:`` block, and the same with the sun high up.
DEFAULT_LIGHT = explicit_illumination(Lighting())
HIGH_SUN = explicit_illumination(Lighting(sun_elevation_deg=80.0))


def _camera(K: np.ndarray, distortion=None) -> Camera:
    R, t = look_at([0.4, -5.0, 2.0], [0.0, 0.0, 0.6])
    kwargs = {} if distortion is None else {"distortion": distortion}
    return Camera(WIDTH, HEIGHT, K, R, t, **kwargs)


IDEAL_CAMERA = _camera(np.array([[150.0, 0.0, 77.3], [0.0, 150.0, 61.8], [0.0, 0.0, 1.0]]))
REAL_CAMERA = _camera(np.array([[148.0, 0.7, 83.6], [0.0, 156.0, 57.2], [0.0, 0.0, 1.0]]),
                      BrownConrady(k1=-0.25, k2=0.06, p1=0.002, p2=-0.003))


def _render_sphere(camera: Camera, point: np.ndarray, spp: int = 256) -> np.ndarray:
    """Linear luminance image of an emissive sphere centred at ``point`` against black, seen by an ideal camera."""
    mi = mitsuba()
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct"},
        "sensor": perspective_sensor(camera, spp),
        "sphere": {"type": "sphere", "center": point.tolist(), "radius": SPHERE_RADIUS_M,
                   "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 1.0}}},
    })
    return np.asarray(mi.render(scene, seed=7), dtype=np.float64)[..., :3].mean(axis=-1)


def _centroid(image: np.ndarray) -> np.ndarray:
    """Intensity-weighted centroid in OpenCV pixel coordinates (pixel (i, j) has its centre at (j, i))."""
    rows, columns = np.indices(image.shape)
    total = image.sum()
    assert total > 1.0, "the sphere is not in the image"
    return np.array([(image * columns).sum() / total, (image * rows).sum() / total])


def test_film_position_is_the_half_pixel_shift() -> None:
    np.testing.assert_array_equal(film_position(np.array([[0.0, 0.0], [9.0, 4.5]])), [[0.5, 0.5], [9.5, 5.0]])


@pytest.mark.parametrize("point", POINTS, ids=["centre", "side", "left", "corner"])
def test_sphere_centroid_matches_projection_for_a_pinhole(point: np.ndarray) -> None:
    assert is_ideal(IDEAL_CAMERA) and ideal_view(IDEAL_CAMERA).ideal is IDEAL_CAMERA
    expected = IDEAL_CAMERA.project(point).uv
    centroid = _centroid(_render_sphere(IDEAL_CAMERA, point))
    assert np.linalg.norm(centroid - expected) < CENTROID_TOLERANCE_PX, (centroid, expected)


@pytest.mark.parametrize("point", POINTS, ids=["centre", "side", "left", "corner"])
def test_sphere_centroid_matches_projection_through_the_warp(point: np.ndarray) -> None:
    view = ideal_view(REAL_CAMERA)
    expected = REAL_CAMERA.project(point).uv
    assert REAL_CAMERA.is_in_image(expected, margin=-8).all()
    centroid = _centroid(view.warp(_render_sphere(view.ideal, point).astype(np.float32)))
    assert np.linalg.norm(centroid - expected) < CENTROID_TOLERANCE_PX, (centroid, expected)


def test_perspective_sensor_refuses_a_real_camera() -> None:
    with pytest.raises(ValueError, match="ideal pinhole"):
        perspective_sensor(REAL_CAMERA, 4)


def _bilinear(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Sample (H, W, C) at float pixel positions (N, 2), pixel centres at integers."""
    u0, v0 = np.floor(uv[:, 0]).astype(int), np.floor(uv[:, 1]).astype(int)
    a, b = (uv[:, 0] - u0)[:, None], (uv[:, 1] - v0)[:, None]
    return ((1 - a) * (1 - b) * image[v0, u0] + a * (1 - b) * image[v0, u0 + 1]
            + (1 - a) * b * image[v0 + 1, u0] + a * b * image[v0 + 1, u0 + 1])


@pytest.mark.parametrize("camera", [
    REAL_CAMERA,
    _camera(np.array([[150.0, 0.0, 80.0], [0.0, 150.0, 60.0], [0.0, 0.0, 1.0]]), BrownConrady(k1=0.15)),
    _camera(np.array([[150.0, 0.0, 80.0], [0.0, 140.0, 60.0], [0.0, 0.0, 1.0]]), TsaiRadial(kappa=0.2)),
], ids=["barrel-skew", "pincushion", "tsai"])
def test_warp_of_a_coordinate_image_agrees_with_project(camera: Camera) -> None:
    """Warp an image whose pixels hold their own coordinates: where the real camera sees a 3-D point, the
    warped image must hold the pixel at which the ideal camera sees it."""
    view = ideal_view(camera)
    ideal = view.ideal
    coordinates = np.indices((ideal.height, ideal.width))[::-1].transpose(1, 2, 0).astype(np.float32)
    warped = view.warp(coordinates)
    assert warped.shape == (camera.height, camera.width, 2)
    # The ideal image covers the whole real view: every real pixel reads from inside it, away from the border.
    assert warped.min() >= 1.0 and (warped.max(axis=(0, 1)) <= [ideal.width - 2, ideal.height - 2]).all()
    rng = np.random.default_rng(3)
    points = camera.unproject(rng.uniform([1, 1], [camera.width - 2, camera.height - 2], (500, 2)))[0]
    points = camera.center + 4.0 * points
    real_uv, ideal_uv = camera.project(points).uv, ideal.project(points).uv
    np.testing.assert_allclose(_bilinear(warped, real_uv), ideal_uv, atol=0.05)


def test_warp_fills_the_real_image_from_the_ideal_one() -> None:
    """A constant ideal image stays constant everywhere in the real image: no black border leaks in."""
    view = ideal_view(REAL_CAMERA)
    white = np.ones((view.ideal.height, view.ideal.width, 3), np.float32)
    np.testing.assert_array_equal(view.warp(white), np.ones((HEIGHT, WIDTH, 3), np.float32))


def test_rendered_paving_lies_where_the_camera_sees_the_walkable_polygon() -> None:
    """The ground texture's orientation and the sensor's pose, end to end: an L-shaped paved area (grey) in
    grass (green) must show up in the real, distorted image exactly where the camera model says it is."""
    polygon = [[-2.0, -1.0], [2.0, -1.0], [2.0, 0.5], [0.0, 0.5], [0.0, 2.5], [-2.0, 2.5]]
    R, t = look_at([0.3, -4.0, 6.0], [0.0, 0.6, 0.0])
    camera = Camera(96, 72, np.array([[70.0, 0.0, 46.0], [0.0, 72.0, 37.0], [0.0, 0.0, 1.0]]), R, t,
                    BrownConrady(k1=-0.15))
    image = render_background(camera, Layout(walkable=[polygon]), HIGH_SUN, spp=8).astype(float)
    paved = image[..., 2] > 0.75 * image[..., 1]  # grey paving is about as blue as green; grass is not
    # Expected: where each pixel's ray meets the ground; pixels whose neighbourhood straddles an edge are skipped.
    offsets = [(0.0, 0.0), (-0.75, -0.75), (-0.75, 0.75), (0.75, -0.75), (0.75, 0.75)]
    grid = np.indices((camera.height, camera.width))[::-1].transpose(1, 2, 0).astype(float)
    inside = []
    for offset in offsets:
        hit = camera.ground_from_pixels(grid + offset)
        assert hit.ok.all()
        inside.append(shapely.contains_xy(Polygon(polygon), hit.points[..., 0], hit.points[..., 1]))
    inside = np.stack(inside)
    clear = inside.all(axis=0) | ~inside.any(axis=0)
    assert inside[0].sum() > 500 and clear.mean() > 0.8
    assert (paved[clear] == inside[0][clear]).mean() > 0.995


def _hull_points(blocker: Box | Cylinder | Wall) -> np.ndarray:
    """3-D points whose convex hull is the (convex) solid."""
    if isinstance(blocker, Box):
        return blocker.corners()
    if isinstance(blocker, Cylinder):
        return densify_segments(blocker.edges(segments=96)).reshape(-1, 3)
    footprint = np.asarray(blocker.footprint().exterior.coords)
    return np.concatenate([np.c_[footprint, np.zeros(len(footprint))],
                           np.c_[footprint, np.full(len(footprint), blocker.height)]])


@pytest.mark.parametrize("blocker", [
    Box(type="box", center=[0.4, 0.8, 0.6], size=[2.0, 0.6, 1.2], yaw=30.0),
    Cylinder(type="cylinder", base=[-0.6, 0.2], radius=0.3, height=1.6),
    Wall(start=[-1.5, 1.5], end=[1.0, 2.2], height=1.2, thickness=0.4),
], ids=["yawed-box", "cylinder", "wall"])
def test_obstacle_silhouette_matches_its_projected_hull(blocker: Box | Cylinder | Wall) -> None:
    """Obstacles and walls stand where the layout says, with its size and yaw conventions: the pixels that see
    them (a depth AOV without the ground) are those inside the convex hull of their projected corners."""
    obstacles, walls = ([], [blocker]) if isinstance(blocker, Wall) else ([blocker], [])
    layout = Layout(walkable=[[[-3.0, -3.0], [3.0, -3.0], [3.0, 3.0]]], obstacles=obstacles, walls=walls)
    R, t = look_at([1.5, -4.5, 4.0], [0.0, 0.8, 0.4])
    camera = Camera(120, 90, np.array([[110.0, 0.0, 57.5], [0.0, 110.0, 46.0], [0.0, 0.0, 1.0]]), R, t)
    scene = layout_scene_dict(layout, DEFAULT_LIGHT, perspective_sensor(camera, 16))
    scene = {key: value for key, value in scene.items() if not key.startswith("ground_")}
    scene["integrator"] = {"type": "aov", "aovs": "depth:depth"}
    mi = mitsuba()
    seen = np.asarray(mi.render(mi.load_dict(scene), seed=0))[..., 0] > 0
    hull = Polygon(camera.project(_hull_points(blocker)).uv).convex_hull
    grid = np.indices(seen.shape)[::-1].transpose(1, 2, 0).astype(float)
    offsets = [(0.0, 0.0), (-0.75, -0.75), (-0.75, 0.75), (0.75, -0.75), (0.75, 0.75)]
    inside = np.stack([shapely.contains_xy(hull, *(grid + offset).transpose(2, 0, 1)) for offset in offsets])
    clear = inside.all(axis=0) | ~inside.any(axis=0)
    assert inside[0].sum() > 100
    np.testing.assert_array_equal(seen[clear], inside[0][clear])


def test_render_background_is_deterministic() -> None:
    layout = Layout(walkable=[[[-2.0, -1.0], [2.0, -1.0], [2.0, 3.0], [-2.0, 3.0]]],
                    obstacles=[{"type": "box", "name": "bench", "center": [0.5, 1.0, 0.25], "size": [1.5, 0.5, 0.5]},
                               {"type": "cylinder", "name": "bollard", "base": [-1.0, 0.0], "radius": 0.1,
                                "height": 0.9}],
                    walls=[{"start": [-3.0, 4.0], "end": [3.0, 4.0], "height": 1.5}])
    camera = REAL_CAMERA.resized(80, 60)
    first = render_background(camera, layout, DEFAULT_LIGHT, spp=4, seed=1)
    assert first.shape == (60, 80, 3) and first.dtype == np.uint8 and first.std() > 5
    np.testing.assert_array_equal(first, render_background(camera, layout, DEFAULT_LIGHT, spp=4, seed=1))
