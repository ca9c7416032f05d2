"""vc-scene init: a starting scene for a new camera from its frames and measured ground points."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from vc.calibration.camera import Camera, look_at
from vc.cli.scene import main as vc_scene
from vc.io import read_image, write_image
from vc.scenes.loader import load_scene
from vc.scenes.starter import ground_points_from_mot

SIZE = (320, 240)
GROUND = np.array([[-4.0, 2.0], [4.0, 2.0], [5.0, 12.0], [-5.0, 12.0], [0.0, 6.0]])


def _camera() -> Camera:
    rotation, translation = look_at([0.0, -10.0, 5.0], [0.0, 6.0, 0.0])
    return Camera(*SIZE, np.array([[300.0, 0.0, 159.5], [0.0, 300.0, 119.5], [0.0, 0.0, 1.0]]), rotation, translation)


def _frames(folder: Path, count: int = 5) -> Path:
    """A folder of frames: a gradient background with a dark square moving across it."""
    folder.mkdir()
    background = np.tile(np.linspace(60, 200, SIZE[0], dtype=np.uint8)[None, :, None], (SIZE[1], 1, 3))
    for index in range(count):
        frame = background.copy()
        frame[100:140, 40 + 50 * index:80 + 50 * index] = 10
        write_image(folder / f"frame{index:03d}.png", frame)
    return folder


def test_init_writes_a_scene_that_loads_from_frames_and_points(tmp_path, capsys):
    camera = _camera()
    image = camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv
    (tmp_path / "points.csv").write_text("u,v,x,y\n" + "".join(
        f"{u:.3f},{v:.3f},{x},{y}\n" for (u, v), (x, y) in zip(image, GROUND, strict=True)))
    out = tmp_path / "my camera"
    assert vc_scene(["init", str(_frames(tmp_path / "frames")), "-o", str(out), "--points",
                     str(tmp_path / "points.csv")]) == 0
    printed = capsys.readouterr().out
    assert "next" in printed and "vc-compile" in printed
    for name in ("scene.yaml", "background.png", "camera.yaml", "overlay.png", "init.json"):
        assert (out / name).stat().st_size > 0
    scene = load_scene(out / "scene.yaml")
    assert scene.name == "my_camera" and scene.video_path == (tmp_path / "frames").resolve()
    np.testing.assert_allclose(scene.camera.center, camera.center, atol=1e-3)
    # The walkable outline is drawn in pixels below the horizon, and people there are at least 16 px tall.
    assert scene.drawn_layout is not None
    outline = np.asarray(scene.drawn_layout.walkable[0])
    assert (outline[:, 1] > camera.horizon_pixels()[:, 1].max()).all()
    report = json.loads((out / "init.json").read_text())
    assert report["fit"]["reprojection_px"]["max"] < 0.01 and report["points"] == len(GROUND)
    # The background is the temporal median: the moving square is gone.
    assert read_image(out / "background.png")[100:140, 40:290].min() >= 60


def test_init_from_a_ground_truth_leaves_its_people_out_of_the_background(tmp_path, capsys):
    """Someone who waits in four of five frames is the plain median; with the ground truth's boxes (the same
    file the camera is solved from) the background shows the scene behind them."""
    camera = _camera()
    feet = camera.project(np.c_[GROUND, np.zeros(len(GROUND))]).uv
    (tmp_path / "frames").mkdir()
    background = np.tile(np.linspace(60, 200, SIZE[0], dtype=np.uint8)[None, :, None], (SIZE[1], 1, 3))
    lines = []
    for index in range(5):
        frame = background.copy()
        if index < 4:
            frame[170:210, 130:170] = 10
            lines.append(f"{index + 1},9,130,170,40,40,1,-1,-1,-1")  # no ground position: not a calibration point
        write_image(tmp_path / "frames" / f"frame{index:03d}.png", frame)
        lines += [f"{index + 1},{k},{u + 0.5 - 5:.3f},{v + 0.5 - 30:.3f},10,30,1,{x},{y},0"
                  for k, ((u, v), (x, y)) in enumerate(zip(feet, GROUND, strict=True))]
    (tmp_path / "gt.txt").write_text("\n".join(lines) + "\n")
    out = tmp_path / "cam"
    assert vc_scene(["init", str(tmp_path / "frames"), "-o", str(out), "--mot-world", str(tmp_path / "gt.txt")]) == 0
    assert "people's boxes left out of the median" in capsys.readouterr().out
    assert read_image(out / "background.png")[170:210, 130:170].min() >= 60, "the waiting person left a ghost"
    report = json.loads((out / "init.json").read_text())
    assert report["background_median"]["people_masked"] and report["points"] == 5 * len(GROUND)


def test_init_takes_a_calibration_file_and_refuses_two_sources(tmp_path, capsys):
    from vc.calibration.ground_points import write_opencv_yaml

    camera = _camera()
    write_opencv_yaml(camera, tmp_path / "given.yaml")
    frame = np.full((SIZE[1], SIZE[0], 3), 128, np.uint8)
    write_image(tmp_path / "view.png", frame)
    assert vc_scene(["init", str(tmp_path / "view.png"), "-o", str(tmp_path / "out"), "--calibration",
                     str(tmp_path / "given.yaml")]) == 0
    document = yaml.safe_load((tmp_path / "out" / "scene.yaml").read_text())
    assert document["calibration"]["format"] == "opencv" and "video" not in document
    assert (tmp_path / "out" / "calibration.yaml").is_file()
    with pytest.raises(SystemExit) as refused:  # argparse: one usage line, status 2
        vc_scene(["init", str(tmp_path / "view.png"), "-o", str(tmp_path / "again"), "--calibration",
                  str(tmp_path / "given.yaml"), "--points", str(tmp_path / "given.yaml")])
    assert refused.value.code == 2 and "not allowed with" in capsys.readouterr().err
    assert not (tmp_path / "again").exists()


def test_feet_of_a_world_ground_truth_are_ground_points(tmp_path):
    path = tmp_path / "gt.txt"
    path.write_text("1,1,100,50,30,100,1,2.5,7.0,0\n"  # feet at (114.5, 149.5)
                    "1,2,200,100,30,140,1,3.0,8.0,0\n"  # cut by the bottom border (240 - 2 px margin)
                    "2,1,90,40,30,100,1,-1,-1,-1\n")  # no world position
    image, ground = ground_points_from_mot(path, image_height=240)
    np.testing.assert_allclose(image, [[114.5, 149.5]])
    np.testing.assert_allclose(ground, [[2.5, 7.0]])
    path.write_text("1,1,100,50,30\n")
    with pytest.raises(Exception, match="line 1"):
        ground_points_from_mot(path, image_height=240)


def test_init_keeps_an_existing_scene_and_leaves_nothing_half_written(tmp_path, capsys):
    frame = np.full((SIZE[1], SIZE[0], 3), 128, np.uint8)
    write_image(tmp_path / "view.png", frame)
    (tmp_path / "edited").mkdir()
    (tmp_path / "edited" / "scene.yaml").write_text("name: mine\n")
    assert vc_scene(["init", str(tmp_path / "view.png"), "-o", str(tmp_path / "edited"), "--points",
                     str(tmp_path / "missing.csv")]) == 2
    assert "exists and is not empty" in capsys.readouterr().err
    assert (tmp_path / "edited" / "scene.yaml").read_text() == "name: mine\n"
    # A calibration refused after the background was made leaves no folder behind.
    assert vc_scene(["init", str(tmp_path / "view.png"), "-o", str(tmp_path / "new"), "--mot-world",
                     str(tmp_path / "missing.txt")]) == 2
    assert "ground-truth file not found" in capsys.readouterr().err
    assert not (tmp_path / "new").exists() and not list(tmp_path.glob(".new.*"))
