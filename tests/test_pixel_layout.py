"""Layouts drawn in pixels of the background, projected onto the ground through the calibration."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
import yaml

from vc.errors import InputError
from vc.scenes.layout import Box, Cylinder
from vc.scenes.loader import load_scene

PETS = Path(__file__).resolve().parent.parent / "examples" / "scenes" / "pets09_s2l1" / "scene.yaml"


def _pixels(camera, points: np.ndarray) -> list[list[float]]:
    projected = camera.project(np.c_[points, np.zeros(len(points))])
    assert projected.ok.all()
    return projected.uv.round(2).tolist()


def _visible_ground(camera, step: int = 4) -> shapely.Polygon:
    """The ground the image shows: its border pixels' ground points (PETS09's horizon is above the image)."""
    width, height = camera.size
    top = [(u, 0) for u in range(0, width, step)]
    right = [(width - 1, v) for v in range(0, height, step)]
    bottom = [(u, height - 1) for u in range(width - 1, 0, -step)]
    left = [(0, v) for v in range(height - 1, 0, -step)]
    hit = camera.ground_from_pixels(np.array(top + right + bottom + left, float))
    assert hit.ok.all()
    return shapely.Polygon(hit.points[:, :2])


def _pets_document() -> dict:
    """PETS09's scene without its data files (the image and video are not shipped: not needed here)."""
    document = yaml.safe_load(PETS.read_text())
    document["image"] = str((PETS.parent / document["image"]).resolve())
    document.pop("video")
    return document


def _redrawn_in_pixels(tmp_path: Path) -> tuple[Path, object, shapely.Geometry]:
    """PETS09's scene with its layout re-authored in pixels, the metric scene, and its walkable ground in view."""
    (tmp_path / "metric.yaml").write_text(yaml.safe_dump(_pets_document(), sort_keys=False))
    scene = load_scene(tmp_path / "metric.yaml", require_image=False)
    camera, layout = scene.camera, scene.layout
    in_view = layout.walkable_area().intersection(_visible_ground(camera))
    obstacles = []
    for obstacle in layout.obstacles:
        if isinstance(obstacle, Cylinder):
            obstacles.append({"type": "cylinder", "base": _pixels(camera, np.array([obstacle.base]))[0],
                              "radius": obstacle.radius, "height": obstacle.height})
        else:
            assert isinstance(obstacle, Box)
            obstacles.append({"type": "box", "footprint": _pixels(camera, obstacle.corners()[:4, :2]),
                              "height": obstacle.size[2], "bottom": obstacle.bottom})
    walls = [{"start": _pixels(camera, np.array([wall.start]))[0], "end": _pixels(camera, np.array([wall.end]))[0],
              "height": wall.height, "thickness": wall.thickness} for wall in layout.walls]
    document = _pets_document()
    document["layout"] = {"frame": "image", "walkable": [_pixels(camera, np.asarray(in_view.exterior.coords)[:-1])],
                          "obstacles": obstacles, "walls": walls}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False))
    return path, scene, in_view


def test_pets09_redrawn_in_pixels_lands_within_5_cm_of_its_metric_layout(tmp_path):
    path, metric, in_view = _redrawn_in_pixels(tmp_path)
    scene = load_scene(path, require_image=False)
    assert scene.drawn_layout is not None and scene.drawn_layout.frame == "image"
    projected = np.asarray(scene.layout.walkable[0])
    np.testing.assert_allclose(projected, np.asarray(in_view.exterior.coords)[:-1], atol=0.05)
    for drawn, original in zip(scene.layout.obstacles, metric.layout.obstacles, strict=True):
        if isinstance(original, Cylinder):
            np.testing.assert_allclose(drawn.base, original.base, atol=0.05)
            continue
        corners = drawn.corners()
        for corner in original.corners():  # the same eight corners, in whatever order
            assert np.linalg.norm(corners - corner, axis=1).min() <= 0.05
    for drawn, original in zip(scene.layout.walls, metric.layout.walls, strict=True):
        np.testing.assert_allclose([drawn.start, drawn.end], [original.start, original.end], atol=0.05)


def test_a_pixel_above_the_horizon_is_refused_by_name(tmp_path):
    document = _pets_document()
    document["layout"] = {"frame": "image", "walkable": [[[100, 500], [600, 500], [600, 300]]],
                          "walls": [{"start": [100, 400], "end": [300, -4000], "height": 3.0}]}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(InputError, match=r"layout\.walls\.0\.end.*above the horizon"):
        load_scene(tmp_path / "scene.yaml", require_image=False)
    document["layout"] = {"frame": "image", "walkable": [[[100, 500], [600, 500], [600, 300]]],
                          "obstacles": [{"type": "box", "footprint": [[100, 400], [200, 400], [300, 400]],
                                         "height": 1.0}]}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(InputError, match=r"layout\.obstacles\.0\.footprint.*collinear"):
        load_scene(tmp_path / "scene.yaml", require_image=False)
    document["layout"] = {"frame": "image", "walkable": [[[100, 500], [600, 500]]]}
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(InputError, match=r"layout\.walkable\.0"):
        load_scene(tmp_path / "scene.yaml", require_image=False)


def test_show_draws_the_pixels_as_given_beside_their_projection(tmp_path):
    from vc.scenes.overlay import DRAWN_COLOUR, draw_overlay
    from vc.scenes.regions import plan_regions

    path, _, _ = _redrawn_in_pixels(tmp_path)
    scene = load_scene(path, require_image=False)
    background = np.zeros((scene.camera.height, scene.camera.width, 3), np.uint8)
    image = draw_overlay(scene, background, plan_regions(scene))
    u, v = np.round(scene.drawn_layout.obstacles[0].base).astype(int)  # the lamp post's base, a dot
    assert tuple(image[v, u]) == DRAWN_COLOUR
