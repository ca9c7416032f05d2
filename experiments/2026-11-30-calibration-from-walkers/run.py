"""Calibration from walking people, measured (frozen, issue 60 item 1; needs walkers_and_solver.patch applied).

Walkers alone found by background subtraction (no network), their head and foot points solved for focal length,
tilt, roll and camera height with a 1.70 m stature prior, bootstrap over tracks; compared with PETS09's Tsai
calibration and TUD-Stadtmitte's camera solved from its ground-truth feet (vc-scene init --mot-world).

    PYTHONPATH=. python experiments/2026-11-30-calibration-from-walkers/run.py PETS_SCENE TUD_SCENE --out results
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from vc.calibration.from_people import pose_of, solve
from vc.calibration.walkers import track_walkers
from vc.deploy.frames import FrameRange, FrameSource, read_frame_image
from vc.scenes.loader import load_scene


def measure(scene_path: Path, frames: FrameRange) -> dict:
    scene = load_scene(scene_path)
    background = read_frame_image(scene.image_path)
    sightings = track_walkers(((frame.number, frame.image) for frame in FrameSource(scene.video_path, frames)),
                              background)
    heads = np.array([sighting.head for sighting in sightings])
    feet = np.array([sighting.foot for sighting in sightings])
    tracks = np.array([sighting.track for sighting in sightings])
    solved = solve(heads, feet, tracks, scene.camera.size)
    truth = pose_of(scene.camera)
    errors = {"focal_share": solved.focal_px / truth["focal_px"] - 1, "tilt_deg": solved.tilt_deg - truth["tilt_deg"],
              "roll_deg": solved.roll_deg - truth["roll_deg"], "height_share": solved.height_m / truth["height_m"] - 1}
    return {"scene": scene.name, "frames": str(frames), "solved": solved.to_dict(),
            "reference": {key: round(value, 4) for key, value in truth.items()},
            "error": {key: round(value, 4) for key, value in errors.items()}}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("pets", type=Path)
    parser.add_argument("tud", type=Path)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name, path, frames in (("pets09", args.pets, FrameRange(1, 400, 2)), ("tud_stadtmitte", args.tud,
                                                                              FrameRange(1, 179, 1))):
        report = measure(path, frames)
        (args.out / f"{name}.json").write_text(json.dumps(report, indent=1))
        print(name, report["error"], report["solved"]["uncertainty"])


if __name__ == "__main__":
    main()
