"""Malformed scene files: each gets one line naming the file and the field, exit status 2, no traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest
from scene_factory import base_scene, modified, write_scene

from vc.cli.scene import main


def _set(path: str, value):
    def edit(scene):
        *parents, last = path.split(".")
        node = scene
        for key in parents:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if value is DELETE:
            del node[last]
        elif isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value
    return edit


DELETE = object()

CASES = {
    "missing field": (modified(_set("name", DELETE)), "name: missing required field"),
    "wrong type": (modified(_set("camera.size", ["wide", 240])), "camera.size.0"),
    "self-intersecting polygon": (
        modified(_set("layout.walkable", [[[0, 0], [4, 4], [4, 0], [0, 4]]])), "layout.walkable: polygon 0: "
                                                                               "polygon is not simple"),
    "walkable area out of view": (
        modified(_set("layout.walkable", [[[-5, -40], [5, -40], [5, -30], [-5, -30]]])),
        "layout.walkable: no walkable area is in view"),
    "negative size": (modified(_set("layout.obstacles.1.size", [2.0, -1.5, 2.5])), "layout.obstacles.1.size.1"),
    "negative radius": (modified(_set("layout.obstacles.0.radius", -0.1)), "layout.obstacles.0.radius"),
    "unknown calibration format": (
        modified(lambda s: (s.pop("camera"), s.update(calibration={"format": "matlab", "path": "cam.mat"}))),
        "calibration.format: unknown calibration format 'matlab'"),
    "missing image": (modified(_set("image", "nowhere.png")), "image: file not found"),
    "image size differs from calibration": (modified(_set("camera.size", [640, 480])),
                                            "image: background.png is 320x240 but the camera is 640x480"),
    "unknown field": (modified(_set("layout.obstacles.0.colour", "red")), "layout.obstacles.0.colour: unknown"),
    "unknown obstacle type": (modified(_set("layout.obstacles.0.type", "sphere")), "layout.obstacles.0"),
    "both camera and calibration": (
        modified(lambda s: s.update(calibration={"format": "tsai-xml", "path": "x.xml"})),
        "give exactly one of camera"),
    "missing calibration file": (
        modified(lambda s: (s.pop("camera"), s.update(calibration={"format": "tsai-xml", "path": "x.xml"}))),
        "calibration.path: file not found"),
    "not a rotation": (modified(_set("camera.R", [[2, 0, 0], [0, 1, 0], [0, 0, 1]])), "camera: R must be a rotation"),
    "bad distortion": (modified(_set("camera.distortion", {"model": "opencv", "k": [0.1]})), "camera.distortion"),
    "height prior reversed": (modified(lambda s: s.update(priors={"height_m": [1.9, 1.5]})), "priors.height_m"),
    "unknown clothing": (modified(lambda s: s.update(priors={"clothing": "autumn"})), "priors.clothing"),
    "unknown region mode": (modified(_set("regions", "many")), "regions"),
    "wall of zero length": (modified(_set("layout.walls.0.end", [-8.0, 16.0])), "layout.walls.0"),
    "missing video": (modified(_set("video", "nowhere.avi")), "video: not found"),
    "negative exposure": (modified(_set("camera.exposure_s", -0.01)), "camera.exposure_s"),
    "time of day without a timezone": (
        modified(_set("lighting", {"location": [51.4, -0.9], "time": "2009-03-20T10:30:00", "north_deg": 90.0})),
        "lighting"),
    "zone with two points": (modified(_set("zones", [{"name": "door", "polygon": [[0, 0], [1, 0]]}])),
                             "zones.0.polygon: a polygon needs at least 3 points"),
    "zone names repeated": (modified(_set("zones", [{"name": "a", "polygon": [[0, 0], [1, 0], [1, 1]]}] * 2)),
                            "zones: zone names must be unique: a repeated"),
    "zone in no frame": (modified(_set("zones", [{"name": "a", "frame": "sky", "polygon": [[0, 0], [1, 0], [1, 1]]}])),
                         "zones.0.frame"),
    "location off the earth": (
        modified(_set("lighting", {"location": [95.0, 0.0], "time": "2009-03-20T10:30:00+00:00", "north_deg": 0.0})),
        "location must be [latitude, longitude]"),
}


@pytest.mark.parametrize("case", CASES)
def test_malformed_scene_gets_one_line_and_status_2(tmp_path, capsys, case):
    scene, expected = CASES[case]
    path = write_scene(tmp_path, scene)
    status = main(["check", str(path)])
    captured = capsys.readouterr()
    assert status == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"error: {path}: ")
    assert expected in lines[0]
    assert "Traceback" not in captured.err + captured.out


def test_yaml_syntax_error_names_the_line(tmp_path, capsys):
    path = write_scene(tmp_path, raw_text="name: broken\nlayout: [unclosed\n")
    assert main(["check", str(path)]) == 2
    assert "line " in capsys.readouterr().err


def test_missing_scene_file(tmp_path, capsys):
    assert main(["check", str(tmp_path / "absent.yaml")]) == 2
    assert "scene file not found" in capsys.readouterr().err


def test_console_script_exit_status_and_no_traceback(tmp_path):
    path = write_scene(tmp_path, modified(_set("layout.obstacles.1.size", [2.0, -1.5, 2.5])))
    result = subprocess.run([sys.executable, "-m", "vc.cli.scene", "check", str(path)], capture_output=True,
                            text=True)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.count("\n") == 1


def test_show_on_bad_scene_leaves_existing_output_untouched(tmp_path, capsys):
    good = write_scene(tmp_path / "good")
    output = tmp_path / "overlay.png"
    assert main(["show", str(good), "-o", str(output)]) == 0
    before = output.read_bytes()
    bad = write_scene(tmp_path / "bad", modified(_set("name", DELETE)))
    assert main(["show", str(bad), "-o", str(output)]) == 2
    assert output.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad", "good", "overlay.json", "overlay.png"]


def test_base_scene_is_valid(tmp_path, capsys):
    assert main(["check", str(write_scene(tmp_path, base_scene()))]) == 0
    assert "regions" in capsys.readouterr().out


def test_inline_rvec_equals_the_rotation_matrix(tmp_path):
    import cv2
    import numpy as np

    from vc.scenes.loader import load_scene

    scene = base_scene()
    R = np.asarray(scene["camera"]["R"])
    rvec = cv2.Rodrigues(R)[0].ravel().tolist()
    rvec_scene = modified(lambda s: (s["camera"].pop("R"), s["camera"].update(rvec=rvec)))
    camera = load_scene(write_scene(tmp_path, rvec_scene)).camera
    np.testing.assert_allclose(camera.R, R, atol=1e-9)
