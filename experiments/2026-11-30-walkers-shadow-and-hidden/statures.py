"""How tall the walkers' blobs stand under the scene's own camera, by their pixel height (frozen, issue 60 item 1; needs
../2026-11-30-calibration-from-walkers/walkers_and_solver.patch and shadow_and_hidden.patch applied).

A blob's stature is the height of the vertical through its foot point's ground position that reaches its head row.
Without bias it would not depend on how many pixels tall the blob is; a trend with size is what moves the solver's
focal length and tilt.

    PYTHONPATH=. python experiments/2026-11-30-walkers-shadow-and-hidden/statures.py SCENE --frames 1:400:2
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from vc.calibration import walkers
from vc.deploy.frames import FrameRange, FrameSource, read_frame_image
from vc.scenes.loader import load_scene

#: Blob heights (pixels) the statures are reported by.
BANDS = ((0, 60), (60, 80), (80, 100), (100, 130), (130, 1000))
STATURES_M = np.linspace(0.5, 3.0, 251)


def statures(camera, heads: np.ndarray, feet: np.ndarray) -> np.ndarray:
    """The stature (m, to 1 cm) of each head over its foot under ``camera``."""
    ground = camera.ground_from_pixels(feet).points
    found = []
    for point, head in zip(ground, heads, strict=True):
        column = np.column_stack([np.full_like(STATURES_M, point[0]), np.full_like(STATURES_M, point[1]), STATURES_M])
        found.append(STATURES_M[np.nanargmin(np.abs(camera.project(column).uv[:, 1] - head[1]))])
    return np.array(found)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", type=Path)
    parser.add_argument("--frames", type=FrameRange.parse, required=True)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    scene = load_scene(args.scene)
    background = read_frame_image(scene.image_path)
    sightings = walkers.track_walkers(((frame.number, frame.image)
                                       for frame in FrameSource(scene.video_path, args.frames)), background)
    heads = np.array([sighting.head for sighting in sightings])
    feet = np.array([sighting.foot for sighting in sightings])
    stature = statures(scene.camera, heads, feet)
    pixels = feet[:, 1] - heads[:, 1]
    report = {"scene": scene.name, "frames": str(args.frames), "sightings": len(stature),
              "stature_quartiles_m": np.round(np.percentile(stature, [25, 50, 75]), 3).tolist(), "by_pixel_height": []}
    for low, high in BANDS:
        chosen = (pixels >= low) & (pixels < high)
        if chosen.any():
            report["by_pixel_height"].append({"pixels": [low, high], "sightings": int(chosen.sum()),
                                              "median_stature_m": round(float(np.median(stature[chosen])), 3)})
    print(json.dumps(report, indent=1))
    if args.out:
        args.out.write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
