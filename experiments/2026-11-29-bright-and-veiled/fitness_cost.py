"""The scene fitness's cost on a PETS09 frame, today's module against another's (0016's, from a checkout of 8a17ba9),
interleaved in one process (frozen experiment, issue 62).

    python experiments/2026-11-29-bright-and-veiled/fitness_cost.py OLD/src/vc/deploy/fitness.py
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path

import cv2
import numpy as np

from vc.deploy import fitness as today
from vc.scenes.loader import load_scene

SCENE = Path(__file__).parents[2] / "examples" / "scenes" / "pets09_s2l1" / "scene.yaml"
REPEATS = 300


def _module(path: Path):
    spec = importlib.util.spec_from_file_location("fitness_before", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path, help="the other fitness.py")
    args = parser.parse_args()
    scene = load_scene(SCENE)
    decode = scene.camera_response().response.decode(np.arange(256, dtype=np.uint8))
    background = cv2.cvtColor(cv2.imread(str(scene.image_path)), cv2.COLOR_BGR2RGB)
    ok, frame = cv2.VideoCapture(str(scene.video_path)).read()
    frame = cv2.cvtColor(frame, cv2.COLOR_BGR2RGB)
    references = {"before": _module(args.before).SceneReference.of_background(background, decode),
                  "today": today.SceneReference.of_background(background, decode)}
    times: dict[str, list[float]] = {name: [] for name in references}
    for _ in range(REPEATS):
        for name, reference in references.items():
            start = time.perf_counter()
            reference.fitness(frame)
            times[name].append(time.perf_counter() - start)
    before, after = (float(np.median(times[name])) * 1e3 for name in ("before", "today"))
    print(f"fitness of PETS09 frame 1: {after:.2f} ms today, {before:.2f} ms before ({after / before:.2f}x)")


if __name__ == "__main__":
    main()
