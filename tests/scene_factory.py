"""A small valid scene written to a temporary folder, with overrides for the malformed-input tests."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import yaml

from vc.calibration.camera import look_at
from vc.io import read_image, write_image

WIDTH, HEIGHT = 320, 240


def base_scene() -> dict:
    R, t = look_at([0.0, -12.0, 6.0], [0.0, 8.0, 0.0])
    return {
        "name": "unit",
        "image": "background.png",
        "camera": {
            "size": [WIDTH, HEIGHT],
            "K": [[300.0, 0.0, 159.5], [0.0, 300.0, 119.5], [0.0, 0.0, 1.0]],
            "distortion": {"model": "opencv", "k": [-0.05, 0.01, 0.0, 0.0, 0.0]},
            "R": R.tolist(),
            "t": t.tolist(),
        },
        "layout": {
            "walkable": [[[-8.0, -4.0], [8.0, -4.0], [8.0, 16.0], [-8.0, 16.0]]],
            "obstacles": [
                {"type": "cylinder", "name": "post", "base": [1.0, 3.0], "radius": 0.1, "height": 4.0},
                {"type": "box", "name": "kiosk", "center": [-3.0, 8.0, 1.25], "size": [2.0, 1.5, 2.5]},
            ],
            "walls": [{"start": [-8.0, 16.0], "end": [8.0, 16.0], "height": 2.0}],
        },
        "regions": "auto",
    }


def write_scene(folder: Path, scene: dict | None = None, image_size: tuple[int, int] = (WIDTH, HEIGHT),
                raw_text: str | None = None) -> Path:
    """Write ``scene`` (default: :func:`base_scene`) and a grey background; returns the YAML path."""
    folder.mkdir(parents=True, exist_ok=True)
    image = np.full((image_size[1], image_size[0], 3), 128, dtype=np.uint8)
    write_image(folder / "background.png", image)
    path = folder / "scene.yaml"
    path.write_text(raw_text if raw_text is not None else yaml.safe_dump(scene or base_scene(), sort_keys=False))
    return path


def modified(edit) -> dict:
    """A copy of the base scene changed by ``edit(scene)``."""
    scene = copy.deepcopy(base_scene())
    edit(scene)
    return scene


#: The camera of :func:`write_people_scene`'s view, and the people's solution of it: 10 % low, 2 degrees shallow.
PEOPLE_TRUTH = {"focal_px": 900.0, "tilt_deg": 25.0, "roll_deg": 0.0, "height_m": 6.5}
PEOPLE_SOLVED = {"focal_px": 940.0, "tilt_deg": 23.0, "roll_deg": 0.0, "height_m": 5.85}


def write_people_scene(folder: Path, background: Path, walkable: list[list[float]]) -> Path:
    """A scene as ``vc-scene init VIDEO`` writes one: ``background`` (960x540), its camera solved from people
    (``walkers.json``, :data:`PEOPLE_SOLVED`, with the spreads of a few dozen people) and ``walkable`` in pixels."""
    folder.mkdir(parents=True, exist_ok=True)
    write_image(folder / "background.png", read_image(background))
    people = {**PEOPLE_SOLVED, "focal_given": False, "stature_m": 1.70, "sightings": 400, "tracks": 40,
              "median_residual": 0.03, "uncertainty": {"focal_px": 60.0, "tilt_deg": 1.0, "roll_deg": 0.4,
                                                       "height_m": 0.2}}
    (folder / "walkers.json").write_text(json.dumps({"size": [960, 540], "people": people, "sightings": []}))
    document = {"name": "people", "image": "background.png",
                "calibration": {"format": "people", "path": "walkers.json"},
                "layout": {"frame": "image", "walkable": [walkable], "obstacles": [], "walls": []}}
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(document, sort_keys=False))
    return path
