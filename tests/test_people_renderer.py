"""The people renderer: pixel convention, coverage, depth and shadow passes, determinism (no anny needed).

A "person" here is any mesh in the renderer's slot topology: an icosphere for the half-pixel test (docs/design.md,
"Conventions": mask centroid within 0.1 px of the projection, with and without lens distortion), a box for
shadows and occlusion.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from vc.calibration.camera import Camera, look_at
from vc.calibration.distortion import BrownConrady
from vc.render.people_renderer import PeopleRenderer, PersonGeometry
from vc.render.relight import explicit_illumination
from vc.scenes.layout import Box, Layout
from vc.scenes.schema import Lighting

WIDTH, HEIGHT = 160, 120
SPHERE = trimesh.creation.icosphere(subdivisions=4, radius=0.12)
CENTROID_TOLERANCE_PX = 0.1
LAYOUT = Layout(walkable=[[[-6.0, -6.0], [6.0, -6.0], [6.0, 6.0], [-6.0, 6.0]]])
#: Points the sphere is centred on: above the ground, near the centre and towards the corners.
SPHERE_CENTRES = np.array([[0.0, 0.0, 0.6], [1.1, 0.5, 1.3], [-1.5, 0.2, 0.4]])

#: The default sun and sky of an explicit ``lighting:`` block.
DEFAULT_LIGHT = explicit_illumination(Lighting())


def _camera(K: np.ndarray, distortion=None) -> Camera:
    R, t = look_at([0.4, -5.0, 2.0], [0.0, 0.0, 0.6])
    return Camera(WIDTH, HEIGHT, K, R, t, **({} if distortion is None else {"distortion": distortion}))


IDEAL = _camera(np.array([[150.0, 0.0, 77.3], [0.0, 150.0, 61.8], [0.0, 0.0, 1.0]]))
DISTORTED = _camera(np.array([[148.0, 0.0, 83.6], [0.0, 156.0, 57.2], [0.0, 0.0, 1.0]]),
                    BrownConrady(k1=-0.25, k2=0.06, p1=0.002, p2=-0.003))


def _sphere_renderer(camera: Camera, spp: int = 64) -> PeopleRenderer:
    return PeopleRenderer(camera, LAYOUT, DEFAULT_LIGHT, np.asarray(SPHERE.faces), len(SPHERE.vertices), max_people=2,
                          spp=spp)


def _sphere(centre: np.ndarray, albedo: float = 0.5) -> PersonGeometry:
    vertices = (np.asarray(SPHERE.vertices) + centre).astype(np.float32)
    return PersonGeometry(vertices, np.full_like(vertices, albedo))


def _centroid(weights: np.ndarray) -> np.ndarray:
    rows, columns = np.indices(weights.shape)
    total = weights.sum()
    assert total > 1.0, "the sphere is not in the image"
    return np.array([(weights * columns).sum() / total, (weights * rows).sum() / total])


@pytest.mark.parametrize("camera", [IDEAL, DISTORTED], ids=["pinhole", "distorted"])
def test_coverage_centroid_matches_the_projection(camera: Camera) -> None:
    renderer = _sphere_renderer(camera)
    for centre in SPHERE_CENTRES:
        passes = renderer.render([_sphere(centre)], seed=1)
        expected = camera.project(centre[None]).uv[0]
        centroid = _centroid(passes.coverage[..., 0])
        assert np.linalg.norm(centroid - expected) < CENTROID_TOLERANCE_PX, (centre, centroid, expected)
        np.testing.assert_allclose(passes.alpha, passes.coverage[..., 0], atol=1e-6)


def test_passes_are_deterministic_and_seeded() -> None:
    renderer = _sphere_renderer(IDEAL, spp=4)
    people = [_sphere(SPHERE_CENTRES[0])]
    first, again = renderer.render(people, seed=5), renderer.render(people, seed=5)
    other = renderer.render(people, seed=6)
    for name in ("beauty", "alpha", "coverage", "shadow", "depth"):
        np.testing.assert_array_equal(getattr(first, name), getattr(again, name))
    assert not np.array_equal(first.beauty, other.beauty)


def test_depth_pass_measures_camera_z_of_the_first_surface() -> None:
    renderer = _sphere_renderer(IDEAL, spp=1)
    centre = SPHERE_CENTRES[0]
    passes = renderer.render([_sphere(centre)], seed=0)
    u, v = np.round(IDEAL.project(centre[None]).uv[0]).astype(int)
    front = IDEAL.world_to_camera(centre[None])[0, 2] - 0.12
    assert passes.depth[v, u] == pytest.approx(front, abs=0.01)
    # Outside the person the pass holds the static scene: the ground, farther away than the sphere.
    ground = IDEAL.ground_from_pixels(np.array([[u, HEIGHT - 2.0]]))
    assert passes.depth[HEIGHT - 2, u] == pytest.approx(IDEAL.world_to_camera(ground.points)[0, 2], rel=1e-3)


def test_second_person_and_obstacles_occlude() -> None:
    wall_in_front = Box(type="box", center=[0.1, -2.0, 1.0], size=[0.6, 0.4, 2.0])
    layout = Layout(walkable=LAYOUT.walkable, obstacles=[wall_in_front])
    renderer = PeopleRenderer(IDEAL, layout, DEFAULT_LIGHT, np.asarray(SPHERE.faces), len(SPHERE.vertices),
                              max_people=2, spp=16)
    behind_box = _sphere(np.array([0.0, 0.0, 0.5]))
    in_the_open = _sphere(np.array([1.1, 0.5, 1.3]))
    passes = renderer.render([behind_box, in_the_open], seed=0)
    # The box (between camera and the first sphere) hides it entirely; the second sphere is fully visible.
    assert passes.coverage[..., 0].sum() < 1.0
    assert passes.coverage[..., 1].sum() == pytest.approx(np.pi * (0.12 * 150 / 5.3) ** 2, rel=0.35)


def test_shadow_pass_darkens_the_ground_where_the_sun_is_blocked_and_only_there() -> None:
    lighting = explicit_illumination(Lighting(sun_azimuth_deg=0.0, sun_elevation_deg=45.0, sun_strength=3.0,
                                                   sky_strength=1.0))
    renderer = PeopleRenderer(IDEAL, LAYOUT, lighting, np.asarray(SPHERE.faces), len(SPHERE.vertices),
                              max_people=1, spp=16)
    centre = np.array([0.0, 0.0, 0.5])
    passes = renderer.render([_sphere(centre)], seed=0)
    # The sun is towards +x at 45 degrees: the shadow's centre lies 0.5 m towards -x on the ground.
    shadow_at = IDEAL.project(np.array([[-0.5, 0.0, 0.0]])).uv[0]
    u, v = np.round(shadow_at).astype(int)
    # Seen from the camera the shadow is a thin ellipse (two pixel rows): take its darkest pixel nearby.
    umbra = passes.shadow[v - 1:v + 2, u - 1:u + 2].min(axis=(0, 1))
    # In the umbra only the sky lights the ground: ratio about sky / (sky + sun * sin 45).
    expected = 1.0 / (1.0 + 3.0 * np.sin(np.radians(45.0)) * np.array([1.0, 0.95, 0.86]) / np.array(
        [0.78, 0.90, 1.15]))
    np.testing.assert_allclose(umbra, expected, atol=0.04)
    far = passes.shadow[:10, :10]
    np.testing.assert_array_equal(far, np.ones_like(far))
    assert (passes.shadow <= 1.0 + 1e-6).all()


def test_static_scene_tests_in_a_kernel_of_their_own_give_the_same_passes() -> None:
    """The CUDA variant's path (OptiX traces one scene per kernel) computes what the CPU's single kernel does."""
    lighting = explicit_illumination(Lighting(sun_azimuth_deg=30.0, sun_elevation_deg=40.0, sun_strength=3.0,
                                                   sky_strength=1.0))
    obstacle = Box(type="box", center=[-0.8, 0.4, 0.5], size=[0.4, 0.4, 1.0])
    layout = Layout(walkable=LAYOUT.walkable, obstacles=[obstacle])
    renderer = PeopleRenderer(IDEAL, layout, lighting, np.asarray(SPHERE.faces), len(SPHERE.vertices), max_people=2,
                              spp=8)
    people = [_sphere(SPHERE_CENTRES[0]), _sphere(SPHERE_CENTRES[2], albedo=0.3)]
    assert not renderer.one_scene_per_kernel  # the CPU variant
    one_kernel = renderer.render(people, seed=3)
    renderer.one_scene_per_kernel = True
    split = renderer.render(people, seed=3)
    assert (one_kernel.shadow < 0.9).any()  # the static scene's tests matter here
    for name in ("beauty", "alpha", "coverage", "shadow", "depth"):
        np.testing.assert_allclose(getattr(split, name), getattr(one_kernel, name), rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize(("elevation", "azimuth", "sky_model"), [
    (0.3, 0.0, "uniform"),  # the sun on the horizon: shadows kilometres long
    (89.9, 0.0, "uniform"),  # overhead
    (30.0, 84.0, "uniform"),  # behind the camera (which looks along +y from -y): shadows fall away from it
    (45.0, 0.0, "cie_overcast"),  # a zero sun under an overcast sky
], ids=["horizon", "zenith", "behind-camera", "overcast"])
def test_extreme_light_keeps_every_pass_finite(elevation: float, azimuth: float, sky_model: str) -> None:
    from dataclasses import replace

    sun = 0.0 if sky_model == "cie_overcast" else 4.0
    light = replace(explicit_illumination(Lighting(sun_azimuth_deg=azimuth, sun_elevation_deg=elevation,
                                                   sun_strength=sun, sky_strength=1.0)), sky_model=sky_model)
    renderer = PeopleRenderer(IDEAL, LAYOUT, light, np.asarray(SPHERE.faces), len(SPHERE.vertices), max_people=2,
                              spp=8)
    passes = renderer.render([_sphere(np.array([0.0, 0.0, 0.5])), _sphere(np.array([1.0, 1.0, 0.3]))], seed=1)
    for layer in (passes.beauty, passes.alpha, passes.coverage, passes.shadow):
        assert np.isfinite(layer).all()
    assert (passes.shadow >= 0).all() and (passes.shadow <= 1.0 + 1e-6).all()
    assert passes.beauty.max() > 0  # the spheres are lit, whatever the sun does
