"""Calibration readers: each format gives the camera it describes; bad files get a clear InputError."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
from conftest import EXAMPLE_SCENES, TOWN_CENTRE, town_centre_camera

from vc.calibration.camera import Camera, look_at
from vc.calibration.distortion import BrownConrady, TsaiRadial
from vc.calibration.readers import read_calibration, read_opencv, read_towncentre_ci, read_tsai_xml
from vc.errors import InputError

TSAI_XML = """<?xml version="1.0" encoding="UTF-8"?>
<Camera name="test">
  <Geometry width="640" height="480" ncx="640" nfx="640" dx="0.005" dy="0.005" dpx="0.005" dpy="0.005"/>
  <Intrinsic focal="4.0" kappa1="0.002" cx="321.5" cy="238.0" sx="1.02"/>
  <Extrinsic tx="100.0" ty="-2000.0" tz="20000.0" rx="2.0" ry="-0.5" rz="-0.4"/>
</Camera>
"""


def test_tsai_xml_matches_the_sensor_model(tmp_path):
    path = tmp_path / "cam.xml"
    path.write_text(TSAI_XML)
    camera = read_tsai_xml(path)
    # Project one point by Tsai's own equations (mm on the sensor) and compare.
    world = np.array([1.5, 2.0, 1.0])
    pc = camera.R @ world + camera.t  # metres
    f, kappa1, dpx, dpy, sx, cx, cy = 4.0, 0.002, 0.005, 0.005, 1.02, 321.5, 238.0
    xu, yu = f * pc[0] / pc[2], f * pc[1] / pc[2]
    # Solve xu = xd (1 + kappa1 rd^2) by fixed point on the sensor plane.
    xd, yd = xu, yu
    for _ in range(200):
        r2 = xd * xd + yd * yd
        xd, yd = xu / (1 + kappa1 * r2), yu / (1 + kappa1 * r2)
    expected = [sx * xd / dpx + cx, yd / dpy + cy]
    np.testing.assert_allclose(camera.project(world).uv, expected, atol=1e-6)
    np.testing.assert_allclose(camera.t, [0.1, -2.0, 20.0])
    assert isinstance(camera.distortion, TsaiRadial)


def test_pets_inline_scene_camera_equals_the_published_xml(pets_data):
    from vc.scenes.loader import read_scene_file

    spec = read_scene_file(EXAMPLE_SCENES / "pets09_s2l1" / "scene.yaml").camera
    xml = read_tsai_xml(pets_data / "View_001.xml")
    np.testing.assert_allclose(spec.K, xml.K, rtol=1e-12)
    np.testing.assert_allclose(spec.R, xml.R, atol=1e-12)
    np.testing.assert_allclose(spec.t, xml.t, atol=1e-12)
    assert spec.distortion.kappa == pytest.approx(xml.distortion.kappa, rel=1e-12)


def write_town_centre_ci(path: Path, camera: Camera) -> None:
    # Quaternion of the world -> camera rotation (x, y, z, w).
    R = camera.R
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    tc = TOWN_CENTRE
    lines = {
        "FocalLengthX": tc["fx"], "FocalLengthY": tc["fy"], "PrincipalPointX": tc["cx"],
        "PrincipalPointY": tc["cy"], "Skew": 0, "TranslationX": camera.t[0], "TranslationY": camera.t[1],
        "TranslationZ": camera.t[2], "RotationX": x, "RotationY": y, "RotationZ": z, "RotationW": w,
        "DistortionK1": tc["k1"], "DistortionK2": tc["k2"], "DistortionP1": tc["p1"], "DistortionP2": tc["p2"],
    }
    path.write_text("".join(f"{key}: {value:.20f}\n" for key, value in lines.items()))


def test_town_centre_ci(tmp_path):
    reference = town_centre_camera()
    path = tmp_path / "TownCentre-calibration.ci"
    write_town_centre_ci(path, reference)
    camera = read_towncentre_ci(path, size=(1920, 1080))
    np.testing.assert_allclose(camera.K, reference.K)
    np.testing.assert_allclose(camera.R, reference.R, atol=1e-12)
    assert camera.distortion == BrownConrady(-0.6015, 4.7020, -0.000475, -0.007823)
    with pytest.raises(InputError, match="size"):
        read_towncentre_ci(path, size=None)
    path.write_text(path.read_text().replace("DistortionK2", "DistortionK9"))
    with pytest.raises(InputError, match="DistortionK2: missing"):
        read_towncentre_ci(path, size=(1920, 1080))


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
@pytest.mark.parametrize("rotation", ["R", "rvec"])
def test_opencv_filestorage(tmp_path, suffix, rotation):
    R, t = look_at([1, -8, 5], [0, 5, 0])
    K = np.array([[800.0, 0, 319.5], [0, 805.0, 241.0], [0, 0, 1]])
    dist = np.array([-0.2, 0.05, 0.001, -0.002, 0.01])
    path = tmp_path / f"cam{suffix}"
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("image_width", 640)
    storage.write("image_height", 480)
    storage.write("camera_matrix", K)
    storage.write("distortion_coefficients", dist.reshape(1, 5))
    storage.write(rotation, R if rotation == "R" else cv2.Rodrigues(R)[0])
    storage.write("tvec", t.reshape(3, 1))
    storage.release()
    camera = read_calibration(path, "opencv")
    assert camera.size == (640, 480)
    np.testing.assert_allclose(camera.K, K)
    np.testing.assert_allclose(camera.R, R, atol=1e-9)
    np.testing.assert_allclose(camera.t, t)
    assert camera.distortion.coefficients == tuple(dist)
    with pytest.raises(InputError, match="file says 640x480"):
        read_opencv(path, size=(1280, 720))


@pytest.mark.parametrize(("content", "reads", "message"), [
    ("<Camera><Geometry width='640'/></Camera>", "tsai-xml", "Intrinsic: element missing"),
    ("<Camera", "tsai-xml", "not valid XML"),
    (TSAI_XML.replace('focal="4.0"', 'focal="abc"'), "tsai-xml", "Intrinsic.focal: not a number"),
    (TSAI_XML.replace('dpx="0.005"', 'dpx="-0.005"'), "tsai-xml", "Geometry.dpx: must be positive"),
    ("%YAML:1.0\n---\nimage_width: 640\n", "opencv", "camera_matrix: missing"),
    ("not: [valid", "opencv", "not a cv::FileStorage"),
])
def test_bad_calibration_files(tmp_path, content, reads, message):
    path = tmp_path / ("cam.xml" if reads == "tsai-xml" else "cam.yaml")
    path.write_text(content)
    with pytest.raises(InputError, match=message) as error:
        read_calibration(path, reads)
    assert str(path) in str(error.value)


def test_unknown_format_and_missing_file(tmp_path):
    with pytest.raises(InputError, match="unknown calibration format 'matlab'"):
        read_calibration(tmp_path / "x.mat", "matlab")
    with pytest.raises(InputError, match="calibration file not found"):
        read_calibration(tmp_path / "absent.xml", "tsai-xml")
