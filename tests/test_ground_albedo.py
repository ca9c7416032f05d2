"""benchmarks/ground_albedo.py: the view elevation it bins the ground by, and the bad-input contract."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import load_benchmark
from test_camera import make_camera

ground_albedo = load_benchmark("ground_albedo")


def test_view_elevation_is_the_rays_angle_above_the_ground():
    camera = make_camera(eye=(0.0, -10.0, 6.0), target=(0.0, 10.0, 0.0))
    elevation = ground_albedo.view_elevation_deg(camera)
    # the principal point (a pixel centre here) looks at the target: 6 m up, 20 m away
    row, column = int(camera.cy + 0.5), int(camera.cx + 0.5)
    assert abs(elevation[row, column] - np.degrees(np.arctan2(6.0, 20.0))) < 0.1
    # lower rows see nearer ground, at a steeper angle; rays above the horizon see no ground
    column = elevation[:, column]
    seen = ~np.isnan(column)
    assert np.all(np.diff(column[seen]) > 0)
    assert np.isnan(ground_albedo.view_elevation_deg(make_camera(target=(0.0, 10.0, 6.0)))[0]).all()


def test_a_missing_scene_is_one_line_and_status_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_status:
        ground_albedo.main(["--scene", str(tmp_path / "nowhere.yaml"), "--out", str(tmp_path)])
    assert exit_status.value.code == 2
    assert "nowhere.yaml" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
