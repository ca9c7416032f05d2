"""Bringing your own camera: the camera solved from measured ground points or an image <-> ground homography."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from vc.calibration.camera import Camera, look_at
from vc.calibration.ground_points import (
    calibrate_from_ground_points,
    camera_from_homography,
    statures_m,
    write_opencv_yaml,
)
from vc.calibration.readers import read_calibration, read_opencv
from vc.cli.scene import main as vc_scene
from vc.errors import InputError
from vc.evaluation.mot import read_mot_boxes
from vc.scenes.loader import load_scene

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
SIZE = (640, 480)
GROUND = np.array([[-3.0, 0.0], [4.0, 1.0], [2.0, 8.0], [-5.0, 6.0], [0.0, 3.0], [6.0, 10.0]])


def _camera() -> Camera:
    rotation, translation = look_at([3.0, -15.0, 7.0], [0.0, 2.0, 0.0])
    return Camera(*SIZE, np.array([[900.0, 0.0, 319.5], [0.0, 900.0, 239.5], [0.0, 0.0, 1.0]]), rotation, translation)


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return math.degrees(math.acos(np.clip((np.trace(a.T @ b) - 1.0) / 2.0, -1.0, 1.0)))


def _write_points(path: Path, image: np.ndarray, ground: np.ndarray) -> Path:
    path.write_text("u,v,x,y\n" + "".join(f"{u},{v},{x},{y}\n" for (u, v), (x, y) in zip(image, ground, strict=True)))
    return path


def test_a_known_camera_is_recovered_from_its_exact_homography():
    camera = _camera()
    ground_to_image = camera.K @ np.column_stack([camera.R[:, 0], camera.R[:, 1], camera.t])
    solved = camera_from_homography(ground_to_image * 3.7, SIZE)  # a homography's scale is arbitrary
    assert solved.fx == pytest.approx(camera.fx, rel=0.01)
    assert _angle_deg(solved.R, camera.R) < 0.5
    np.testing.assert_allclose(solved.center, camera.center, atol=1e-6)


def test_ground_points_give_back_the_camera_they_were_measured_with(tmp_path):
    camera = _camera()
    image = camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv
    fit = calibrate_from_ground_points(image, GROUND, SIZE)
    assert fit.focal_solved and fit.camera.fx == pytest.approx(900.0, rel=1e-6)
    assert fit.errors_px.max() < 1e-6 and _angle_deg(fit.camera.R, camera.R) < 1e-4
    # Noisy measurements still fit, and a given focal length is kept.
    noisy = image + np.random.default_rng(0).normal(0.0, 0.5, image.shape)
    given = calibrate_from_ground_points(noisy, GROUND, SIZE, focal_px=900.0)
    assert not given.focal_solved and given.camera.fx == 900.0 and given.errors_px.max() < 2.0
    # The solved camera written as OpenCV YAML reads back as the same camera.
    write_opencv_yaml(fit.camera, tmp_path / "camera.yaml")
    again = read_opencv(tmp_path / "camera.yaml")
    np.testing.assert_allclose(again.K, fit.camera.K)
    np.testing.assert_allclose(again.R, fit.camera.R, atol=1e-12)


def test_a_scene_can_name_ground_points_as_its_calibration(tmp_path):
    camera = _camera()
    _write_points(tmp_path / "points.csv", camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv, GROUND * 100)
    document = {"name": "own", "image": "background.png",
                "calibration": {"format": "ground-points", "path": "points.csv", "size": list(SIZE), "units": "cm"},
                "layout": {"walkable": [[[-6, -2], [7, -2], [7, 12], [-6, 12]]]}}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(document))
    scene = load_scene(tmp_path / "scene.yaml", require_image=False)
    assert scene.camera.fx == pytest.approx(900.0, rel=1e-6)  # centimetres became metres
    np.testing.assert_allclose(scene.camera.center, camera.center, atol=1e-6)
    document["calibration"].pop("size")
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(InputError, match="needs the image size"):
        load_scene(tmp_path / "scene.yaml", require_image=False)


def test_statures_follow_the_boxes_of_people_of_known_height():
    camera = _camera()
    feet = np.array([[0.0, 3.0, 0.0], [4.0, 9.0, 0.0]])
    heads = feet + np.array([0.0, 0.0, 1.8])
    feet_uv, head_uv = camera.project(feet).uv, camera.project(heads).uv
    half = 15.0
    boxes = np.column_stack([feet_uv[:, 0] - half + 0.5, head_uv[:, 1] + 0.5, feet_uv[:, 0] + half + 0.5,
                             feet_uv[:, 1] + 0.5])
    heights, ok = statures_m(camera, boxes)
    assert ok.all()
    np.testing.assert_allclose(heights, 1.8, atol=0.02)  # the head is not exactly above the feet in the image


def _bad_points(tmp_path: Path, name: str) -> Path:
    camera = _camera()
    image = camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv
    path = tmp_path / f"{name}.csv"
    if name == "too few":
        return _write_points(path, image[:3], GROUND[:3])
    if name == "collinear":
        line = np.column_stack([np.linspace(-3, 3, 5), np.linspace(0, 6, 5)])
        return _write_points(path, camera.project(np.c_[line, np.zeros(5)]).uv, line)
    if name == "nan":
        path.write_text("u,v,x,y\n1,2,3,nan\n")
        return path
    if name == "off the image":
        shifted = image.copy()
        shifted[0, 0] += 700.0
        return _write_points(path, shifted, GROUND)
    if name == "text in a number column":
        path.write_text("u,v,x,y\n1,2,3,4\n5,six,7,8\n")
        return path
    if name == "three columns":
        path.write_text("1,2,3\n")
        return path
    if name == "mirrored ground axes":
        return _write_points(path, image, GROUND * [1.0, -1.0])
    if name == "shuffled pairs":
        return _write_points(path, image, GROUND[::-1])
    raise ValueError(name)


@pytest.mark.parametrize(("name", "message"), [
    ("too few", "needs at least 4 points, got 3"),
    ("collinear", "collinear"),
    ("nan", "not finite"),
    ("off the image", "lies outside the 640x480 image"),
    ("text in a number column", "line 3: not a number"),
    ("three columns", "expected u, v, x, y, got 3 values"),
    ("mirrored ground axes", "below the ground|mirrored"),
    ("shuffled pairs", "below the ground|in front|cannot solve the focal"),
])
def test_bad_ground_points_get_one_clear_line_and_status_2(tmp_path, capsys, name, message):
    path = _bad_points(tmp_path, name)
    assert vc_scene(["calibrate", str(path), "--size", *map(str, SIZE), "-o", str(tmp_path / "camera.yaml")]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and str(path) in error
    assert re.search(message, error), error
    assert not (tmp_path / "camera.yaml").exists()


@pytest.mark.parametrize(("content", "message"), [
    ("1 0 0\n0 1 0\n0 0 0\n", "singular"),
    ("1 0 0 0 1 0 0 0\n", "9 values"),
    ("1 0 0 0 one 0 0 0 1\n", "every value must be a number"),
    ("1 0 0 0 1 0 0 0 inf\n", "NaN or inf"),
    # image -> ground with the ground's line at infinity below the image: the image shows only sky
    ("1 0 0 0 1 0 0 -0.01 -1\n", "above the horizon|below the ground|cannot solve the focal"),
])
def test_bad_homographies_get_one_clear_line_and_status_2(tmp_path, capsys, content, message):
    path = tmp_path / "H.txt"
    path.write_text(content)
    assert vc_scene(["calibrate", str(path), "--format", "homography", "--size", *map(str, SIZE), "-o",
                     str(tmp_path / "camera.yaml")]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and re.search(message, error), error


def test_a_file_calibration_refuses_a_focal_length(tmp_path):
    camera = _camera()
    write_opencv_yaml(camera, tmp_path / "camera.yaml")
    with pytest.raises(InputError, match="only a solved calibration"):
        read_calibration(tmp_path / "camera.yaml", "opencv", focal_px=800.0)


def test_an_eth_style_homography_file_is_read_as_image_to_ground(tmp_path):
    camera = _camera()
    ground_to_image = camera.K @ np.column_stack([camera.R[:, 0], camera.R[:, 1], camera.t])
    np.savetxt(tmp_path / "H.txt", np.linalg.inv(ground_to_image))
    solved = read_calibration(tmp_path / "H.txt", "homography", SIZE)
    assert solved.fx == pytest.approx(900.0, rel=0.01) and _angle_deg(solved.R, camera.R) < 0.5


@pytest.mark.pets
def test_pets09_from_eight_ground_points_matches_its_tsai_calibration(pets_data, tmp_path):
    report = tmp_path / "solution.json"
    assert vc_scene(["calibrate", str(SCENES / "pets09_s2l1" / "ground_points.csv"), "--size", "768", "576",
                     "-o", str(tmp_path / "camera.yaml"), "--json", str(report)]) == 0
    solution = yaml.safe_load(report.read_text())
    assert solution["reprojection_px"]["max"] <= 1.0
    camera = read_opencv(tmp_path / "camera.yaml")
    truth = read_mot_boxes(pets_data / "gt_dev_frames_0001-0400.txt")
    heights, ok = statures_m(camera, np.concatenate([truth[frame] for frame in sorted(truth)]))
    assert ok.mean() > 0.95 and 1.70 <= float(np.median(heights[ok])) <= 1.80


def test_an_unwritable_camera_file_is_one_line_and_status_2(tmp_path, capsys):
    camera = _camera()
    points = _write_points(tmp_path / "points.csv", camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv, GROUND)
    (tmp_path / "file").write_text("")
    assert vc_scene(["calibrate", str(points), "--size", *map(str, SIZE), "-o",
                     str(tmp_path / "file" / "camera.yaml")]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "cannot write" in error
