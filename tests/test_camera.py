"""Camera maths: round trips to 1e-6 px, hard cases flagged (never silent NaN), resize and crop."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import pixel_grid, town_centre_camera
from hypothesis import given, settings
from hypothesis import strategies as st

from vc.calibration.camera import Camera, look_at, rotation_from_quaternion, rotation_xyz
from vc.calibration.distortion import BrownConrady, NoDistortion, TsaiRadial


def make_camera(distortion=None, eye=(0.0, -10.0, 6.0), target=(0.0, 10.0, 0.0), size=(640, 480), f=600.0):
    R, t = look_at(eye, target)
    K = np.array([[f, 0, size[0] / 2 - 0.5 + 7.0], [0, f * 1.01, size[1] / 2 - 0.5 - 5.0], [0, 0, 1]])
    return Camera(*size, K=K, R=R, t=t, distortion=distortion or NoDistortion())


CAMERAS = {
    "pinhole": make_camera(),
    "opencv": make_camera(BrownConrady(-0.25, 0.08, 0.001, -0.0015, -0.01)),
    "tsai": make_camera(TsaiRadial(0.16)),
    "town-centre": town_centre_camera(),
}


@pytest.mark.parametrize("name", CAMERAS)
def test_project_unproject_round_trip_within_1e6_px(name):
    camera = CAMERAS[name]
    pixels = pixel_grid(camera)
    rays, ok = camera.unproject(pixels)
    assert ok.all(), f"undistortion failed at {pixels[~ok][:5]}"
    points = camera.center + 7.5 * rays
    projection = camera.project(points)
    assert projection.ok.all()
    assert np.abs(projection.uv - pixels).max() < 1e-6


def test_pets_round_trip_and_undistortion_everywhere(pets_camera):
    pixels = pixel_grid(pets_camera, step=4)
    rays, ok = pets_camera.unproject(pixels)
    assert ok.all()
    back = pets_camera.project(pets_camera.center + 20.0 * rays)
    assert np.abs(back.uv - pixels).max() < 1e-6


def test_town_centre_undistortion_converges_everywhere_inside_the_image():
    camera = town_centre_camera()
    pixels = pixel_grid(camera, step=8)
    normalised, ok = camera.distortion.undistort(camera.normalised_from_pixels(pixels))
    assert ok.all() and np.isfinite(normalised).all()
    redistorted, ok2 = camera.distortion.distort(normalised)
    assert ok2.all()
    assert np.abs(camera.pixels_from_normalised(redistorted) - pixels).max() < 1e-6


def test_points_behind_the_camera_are_flagged_not_projected():
    camera = CAMERAS["opencv"]
    behind = camera.center - 5.0 * camera.R[2]  # 5 m behind, on the optical axis
    on_plane = camera.center + 2.0 * camera.R[0]  # in the camera plane (z = 0)
    projection = camera.project(np.array([behind, on_plane, camera.center + 3.0 * camera.R[2]]))
    assert projection.in_front.tolist() == [False, False, True]
    assert np.isnan(projection.uv[:2]).all() and np.isfinite(projection.uv[2]).all()


def test_pixels_above_the_horizon_do_not_hit_the_ground():
    # A camera looking almost horizontally: the horizon crosses the image.
    camera = make_camera(eye=(0, 0, 3.0), target=(0, 50, 2.0))
    horizon = camera.horizon_pixels()
    inside = horizon[camera.is_in_image(horizon)]
    assert len(inside) > 0, "the horizon should cross this image"
    v_horizon = np.interp(320.0, inside[:, 0], inside[:, 1])
    hits = camera.ground_from_pixels(np.array([[320.0, v_horizon - 20], [320.0, v_horizon + 20]]))
    assert hits.ok.tolist() == [False, True]
    assert np.isnan(hits.points[0]).all()
    np.testing.assert_allclose(hits.points[1, 2], 0.0, atol=1e-9)


def test_rays_parallel_to_the_ground_are_flagged():
    camera = make_camera(eye=(0, 0, 3.0), target=(0, 50, 3.0))  # optical axis horizontal
    principal = np.array([[camera.cx, camera.cy]])
    hits = camera.ground_from_pixels(principal)
    assert not hits.ok[0] and np.isnan(hits.points).all()


def test_distortion_outside_its_one_to_one_domain_is_flagged():
    # k1 strongly negative: r (1 + k1 r^2) folds back at r = 1 / sqrt(3 |k1|).
    model = BrownConrady(k1=-0.5)
    r_fold = 1 / np.sqrt(1.5)
    _, ok = model.distort(np.array([[0.5 * r_fold, 0.0], [1.5 * r_fold, 0.0]]))
    assert ok.tolist() == [True, False]
    tsai = TsaiRadial(-0.4)
    _, ok = tsai.undistort(np.array([[0.1, 0.0], [2.0, 0.0]]))
    assert ok.tolist() == [True, False]


def test_unreachable_distorted_point_reports_failure():
    model = BrownConrady(k1=-0.5)
    # The distorted radius peaks at (2/3) r_fold; beyond it no undistorted point maps there.
    r_peak = (2 / 3) / np.sqrt(1.5)
    points, ok = model.undistort(np.array([[0.9 * r_peak, 0.0], [1.2 * r_peak, 0.0]]))
    assert ok.tolist() == [True, False]
    assert np.isfinite(points[0]).all() and np.isnan(points[1]).all()


@pytest.mark.parametrize("name", ["opencv", "tsai"])
def test_resize_and_crop_move_pixels_like_the_image_does(name):
    camera = CAMERAS[name]
    points = camera.center + 9.0 * camera.unproject(pixel_grid(camera, 64))[0]
    uv = camera.project(points).uv
    crop = camera.cropped(100, 40, 300, 200)
    np.testing.assert_allclose(crop.project(points).uv, uv - [100, 40], atol=1e-9)
    half = camera.resized(camera.width // 2, camera.height // 2)
    # Pixel centres at integers: the image edge -0.5 stays at -0.5, so u' = (u + 0.5) / 2 - 0.5.
    np.testing.assert_allclose(half.project(points).uv, (uv + 0.5) / 2 - 0.5, atol=1e-9)


def test_tsai_rotation_convention_and_quaternion():
    rx, ry, rz = 0.3, -0.2, 1.1
    R = rotation_xyz(rx, ry, rz)
    # Rz Ry Rx applied to x-axis: first rotation about x leaves it, then y, then z.
    expected = np.array([np.cos(ry) * np.cos(rz), np.cos(ry) * np.sin(rz), -np.sin(ry)])
    np.testing.assert_allclose(R[:, 0], expected, atol=1e-12)
    half = 0.5 * 0.7
    np.testing.assert_allclose(rotation_from_quaternion(0, 0, np.sin(half), np.cos(half)),
                               rotation_xyz(0, 0, 0.7), atol=1e-12)


def test_invalid_cameras_are_rejected():
    R, t = look_at([0, -5, 3], [0, 5, 0])
    with pytest.raises(ValueError, match="focal"):
        Camera(640, 480, K=np.diag([-1.0, 500.0, 1.0]), R=R, t=t)
    with pytest.raises(ValueError, match="rotation"):
        Camera(640, 480, K=np.diag([500.0, 500.0, 1.0]), R=2 * R, t=t)
    with pytest.raises(ValueError, match="NaN"):
        Camera(640, 480, K=np.diag([500.0, 500.0, 1.0]), R=R, t=[0, np.nan, 0])


# --- property-based tests --------------------------------------------------------------------------------------
coefficient = st.floats(-0.3, 0.3)
small = st.floats(-0.002, 0.002)


@settings(max_examples=60, deadline=None)
@given(k1=coefficient, k2=st.floats(-0.1, 0.1), p1=small, p2=small,
       x=st.floats(-0.6, 0.6), y=st.floats(-0.45, 0.45))
def test_brown_conrady_undistort_inverts_distort(k1, k2, p1, p2, x, y):
    model = BrownConrady(k1, k2, p1, p2)
    distorted, ok = model.distort(np.array([[x, y]]))
    if not ok[0]:
        return  # outside the one-to-one domain: flagged, nothing to invert
    undistorted, ok = model.undistort(distorted)
    assert ok[0]
    np.testing.assert_allclose(undistorted[0], [x, y], atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(kappa=st.floats(-0.5, 0.5), x=st.floats(-0.6, 0.6), y=st.floats(-0.6, 0.6))
def test_tsai_distort_inverts_undistort(kappa, x, y):
    model = TsaiRadial(kappa)
    undistorted, ok = model.undistort(np.array([[x, y]]))
    if not ok[0]:
        return
    distorted, ok = model.distort(undistorted)
    assert ok[0]
    np.testing.assert_allclose(distorted[0], [x, y], atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-30, 30), y=st.floats(-30, 30), z=st.floats(-5, 10))
def test_projection_is_finite_exactly_where_flagged_ok(x, y, z):
    for camera in CAMERAS.values():
        projection = camera.project(np.array([[x, y, z]]))
        assert np.isfinite(projection.uv[0]).all() == bool(projection.ok[0])
        if projection.ok[0]:
            ray, ok = camera.unproject(projection.uv)
            direction = np.array([x, y, z]) - camera.center
            if ok[0] and np.linalg.norm(direction) > 1e-3:
                np.testing.assert_allclose(ray[0], direction / np.linalg.norm(direction), atol=1e-7)


@settings(max_examples=40, deadline=None)
@given(u=st.floats(0, 639), v=st.floats(0, 479))
def test_ground_hits_lie_on_the_ground_and_project_back(u, v):
    camera = CAMERAS["opencv"]
    hit = camera.ground_from_pixels(np.array([[u, v]]))
    if hit.ok[0]:
        assert abs(hit.points[0, 2]) < 1e-9
        np.testing.assert_allclose(camera.project(hit.points).uv[0], [u, v], atol=1e-6)
    else:
        assert np.isnan(hit.points[0]).all()


@pytest.mark.parametrize("name", CAMERAS)
def test_dict_form_round_trips(name):
    from vc.calibration.camera import camera_from_dict

    camera = CAMERAS[name]
    again = camera_from_dict(camera.to_dict())
    points = camera.center + 5.0 * camera.unproject(pixel_grid(camera, 80))[0]
    np.testing.assert_array_equal(again.project(points).uv, camera.project(points).uv)
