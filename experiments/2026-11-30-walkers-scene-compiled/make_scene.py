"""PETS09's scene with the camera solved from its walkers (``vc-scene init`` with no points) in place of the Tsai
calibration, and its layout drawn in pixels as a user would draw it in ``vc-scene edit`` (frozen, issue 60's second
acceptance line).

    PYTHONPATH=. python experiments/2026-11-30-walkers-scene-compiled/make_scene.py INIT_DIR OUT_DIR

``INIT_DIR``: what ``vc-scene init vtest.avi -o INIT_DIR --frames 1:400:2`` wrote (its ``camera.yaml``). The layout's
pixels are PETS09's metric layout seen through the Tsai camera: the walkable ground in view, the 14 obstacles and the
wall, with their heights in metres as a user types them. The background, priors, lighting, effects and region
settings are PETS09's own, so that the two scenes differ in their camera alone.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np
import shapely
import yaml

from vc.scenes.layout import Box, Cylinder
from vc.scenes.loader import load_scene

PETS = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "pets09_s2l1" / "scene.yaml"


def pixels(camera, points: np.ndarray) -> list[list[float]]:
    projected = camera.project(np.c_[points, np.zeros(len(points))])
    assert projected.ok.all()
    return projected.uv.round(2).tolist()


def visible_ground(camera, step: int = 4) -> shapely.Polygon:
    width, height = camera.size
    border = ([(u, 0) for u in range(0, width, step)] + [(width - 1, v) for v in range(0, height, step)]
              + [(u, height - 1) for u in range(width - 1, 0, -step)] + [(0, v) for v in range(height - 1, 0, -step)])
    hit = camera.ground_from_pixels(np.array(border, float))
    assert hit.ok.all()
    return shapely.Polygon(hit.points[:, :2])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("init", type=Path)
    parser.add_argument("out", type=Path)
    args = parser.parse_args()
    scene = load_scene(PETS)
    camera, layout = scene.camera, scene.layout
    in_view = layout.walkable_area().intersection(visible_ground(camera))
    obstacles = []
    for obstacle in layout.obstacles:
        if isinstance(obstacle, Cylinder):
            obstacles.append({"type": "cylinder", "base": pixels(camera, np.array([obstacle.base]))[0],
                              "radius": obstacle.radius, "height": obstacle.height})
        else:
            assert isinstance(obstacle, Box)
            obstacles.append({"type": "box", "footprint": pixels(camera, obstacle.corners()[:4, :2]),
                              "height": obstacle.size[2], "bottom": obstacle.bottom})
    walls = [{"start": pixels(camera, np.array([wall.start]))[0], "end": pixels(camera, np.array([wall.end]))[0],
              "height": wall.height, "thickness": wall.thickness} for wall in layout.walls]
    document = yaml.safe_load(PETS.read_text())
    document.pop("camera")
    document["name"] = "pets09_s2l1_walkers"
    document["image"] = str(scene.image_path)
    document["video"] = str(scene.video_path)
    document["calibration"] = {"format": "opencv", "path": "camera.yaml", "response": "srgb"}
    document["layout"] = {"frame": "image", "walkable": [pixels(camera, np.asarray(in_view.exterior.coords)[:-1])],
                          "obstacles": obstacles, "walls": walls}
    args.out.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(args.init / "camera.yaml", args.out / "camera.yaml")
    (args.out / "scene.yaml").write_text(yaml.safe_dump(document, sort_keys=False, width=120))
    print(f"wrote {args.out / 'scene.yaml'}")


if __name__ == "__main__":
    main()
