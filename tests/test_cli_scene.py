"""vc-scene end to end: check writes its JSON, show draws an overlay, background recovers the empty scene."""

from __future__ import annotations

import json

import cv2
import numpy as np
from scene_factory import write_scene

from vc.cli.scene import main
from vc.io import read_image


def test_check_prints_summary_and_writes_json(tmp_path, capsys):
    path = write_scene(tmp_path)
    assert main(["check", str(path), "--json", str(tmp_path / "out" / "check.json")]) == 0
    out = capsys.readouterr().out
    assert "camera  320x240" in out and "regions" in out
    summary = json.loads((tmp_path / "out" / "check.json").read_text())
    assert summary["scene"] == "unit" and len(summary["regions"]) >= 2
    for region in summary["regions"]:
        low, high = region["person_height_px"]
        assert 0 < low < high
        assert region["input_size"][0] % 16 == 0


def test_show_draws_geometry_over_the_background(tmp_path, capsys):
    path = write_scene(tmp_path)  # plain grey background: every non-grey pixel was drawn
    output = tmp_path / "overlay.png"
    assert main(["show", str(path), "-o", str(output)]) == 0
    image = read_image(output)
    assert image.shape == (240, 320, 3)
    drawn = np.any(image != 128, axis=-1)
    assert 0.05 < drawn.mean() < 0.99
    # The post (1 m right of centre, 3 m ahead) is drawn in the obstacle colour.
    red = (image[..., 0] > 200) & (image[..., 1] < 110) & (image[..., 2] < 110)
    assert red.sum() > 10
    assert json.loads(output.with_suffix(".json").read_text())["scene"] == "unit"


def _write_video(path, frames):
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10, frames[0].shape[1::-1])
    for frame in frames:
        writer.write(cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
    writer.release()


def test_background_is_the_temporal_median(tmp_path, capsys):
    rng = np.random.default_rng(0)
    background = (rng.integers(40, 200, (1, 1, 3)) + np.linspace(0, 50, 96)[None, :, None]).astype(np.uint8)
    background = np.repeat(background, 64, axis=0)
    frames = []
    for i in range(40):
        frame = background.copy()
        x = (i * 7) % 80
        frame[20:44, x:x + 12] = (250, 20, 20)  # a "person" walking across
        frames.append(frame)
    video = tmp_path / "walk.avi"
    _write_video(video, frames)
    output = tmp_path / "bg.png"
    assert main(["background", str(video), "-o", str(output), "--frames", "40"]) == 0
    result = read_image(output).astype(int)
    assert np.abs(result - background.astype(int)).mean() < 3.0  # MJPG is lossy
    assert np.abs(result - background.astype(int))[20:44].max() < 30, "the walker must be gone"
    report = json.loads(output.with_suffix(".json").read_text())
    assert report["frames_used"] == 40


def test_background_leaves_out_the_boxes_of_people_who_stood_still(tmp_path, capsys):
    """A person who waits in one place for 70 % of the clip is the plain median there (a ghost); with their boxes
    given, the median is taken over the frames that show the scene, and a place covered in every frame is
    counted rather than silently kept."""
    background = np.repeat(np.linspace(60, 180, 96, dtype=np.uint8)[None, :, None], 64, axis=0).repeat(3, axis=2)
    frames, lines = [], []
    for i in range(30):
        frame = background.copy()
        x = 10 if i < 21 else 10 + 3 * (i - 20)  # waits, then walks off
        frame[20:50, x:x + 12] = (20, 20, 20)
        frame[0:8, 88:96] = (250, 250, 250)  # always covered (a box in every frame)
        frames.append(frame)
        lines += [f"{i + 1},1,{x},20,12,30,1,0,0,0", f"{i + 1},2,88,0,8,8,1,0,0,0"]
    video, truth = tmp_path / "wait.avi", tmp_path / "gt.txt"
    _write_video(video, frames)
    truth.write_text("\n".join(lines) + "\n")
    plain, masked = tmp_path / "plain.png", tmp_path / "masked.png"
    assert main(["background", str(video), "-o", str(plain), "--frames", "30"]) == 0
    assert main(["background", str(video), "-o", str(masked), "--frames", "30", "--people", str(truth)]) == 0
    waiting = (slice(22, 48), slice(12, 20))
    assert np.abs(read_image(plain).astype(int) - background)[waiting].mean() > 40, "the plain median keeps a ghost"
    assert np.abs(read_image(masked).astype(int) - background)[waiting].max() < 30, "the masked one does not"
    report = json.loads(masked.with_suffix(".json").read_text())
    assert report["people_masked"] and 0 < report["never_free_fraction"] < 0.05
    assert "covered by someone in every frame" in capsys.readouterr().out


def test_background_rejects_unreadable_video(tmp_path, capsys):
    video = tmp_path / "broken.avi"
    video.write_bytes(b"not a video at all")
    output = tmp_path / "bg.png"
    assert main(["background", str(video), "-o", str(output)]) == 2
    assert "broken.avi" in capsys.readouterr().err
    assert not output.exists() and list(tmp_path.iterdir()) == [video]
