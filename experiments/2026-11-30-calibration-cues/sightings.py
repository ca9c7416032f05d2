"""Head and foot sightings for the calibration probe (frozen, issue 60 item 1; needs the walker patches and
segment_heights.patch applied, see README.md).

    PYTHONPATH=. python experiments/2026-11-30-calibration-cues/sightings.py blobs SCENE OUT.npz
    PYTHONPATH=. python experiments/2026-11-30-calibration-cues/sightings.py keypoints VC_RUN_DIR SCENE OUT.npz

``blobs``: walkers alone by background subtraction (the shadow patch's ``track_walkers``), frames 1-400 every 2nd;
a 1.70 m stature from the ground. ``keypoints``: a ``vc-run`` of a bundle compiled for the camera, every confident
person (ears and ankles at confidence 0.5 or more, clear of the frame's edges), the ears' and the ankles' midpoints,
their heights above the ground 0.92 and 0.09 of a 1.70 m stature (the renders' body model: UPRIGHT_OFFSETS).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from vc.calibration.walkers import track_walkers
from vc.deploy.frames import FrameRange, FrameSource, read_frame_image
from vc.scenes.loader import load_scene

STATURE_M = 1.70
EARS_SHARE, ANKLES_SHARE = 0.92, 0.09
CONFIDENT = 0.5


def blobs(scene_path: Path, out: Path) -> None:
    scene = load_scene(scene_path)
    found = track_walkers(((frame.number, frame.image) for frame in FrameSource(scene.video_path,
                                                                                FrameRange(1, 400, 2))),
                          read_frame_image(scene.image_path))
    np.savez(out, heads=np.array([s.head for s in found]), feet=np.array([s.foot for s in found]),
             tracks=np.array([s.track for s in found]), frames=np.array([s.frame for s in found]),
             low=0.0, high=STATURE_M)


def keypoints(run: Path, scene_path: Path, out: Path) -> None:
    width, height = load_scene(scene_path).camera.size
    heads, feet, tracks, frames = [], [], [], []
    for line in (run / "detections.jsonl").read_text().splitlines():
        record = json.loads(line)
        for person in record["people"]:
            if person.get("coasted") or person.get("weak") or person.get("track") is None:
                continue
            points = np.array(person["keypoints"])
            x0, y0, x1, y1 = person["box"]
            if points[[3, 4, 15, 16], 2].min() < CONFIDENT or x0 < 2 or y0 < 2 or x1 > width - 3 or y1 > height - 3:
                continue
            heads.append(points[3:5, :2].mean(axis=0))
            feet.append(points[15:17, :2].mean(axis=0))
            tracks.append(person["track"])
            frames.append(record["frame"])
    np.savez(out, heads=np.array(heads), feet=np.array(feet), tracks=np.array(tracks), frames=np.array(frames),
             low=ANKLES_SHARE * STATURE_M, high=EARS_SHARE * STATURE_M)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("kind", choices=("blobs", "keypoints"))
    parser.add_argument("paths", type=Path, nargs="+")
    args = parser.parse_args()
    if args.kind == "blobs":
        blobs(*args.paths)
    else:
        keypoints(*args.paths)


if __name__ == "__main__":
    main()
