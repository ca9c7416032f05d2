"""The camera from head and foot sightings, with "a walker keeps their speed" as a second cue (frozen, issue 60
item 1; Bose & Grimson, "Ground plane rectification by tracking moving objects", VS-PETS 2003).

    PYTHONPATH=. python experiments/2026-11-30-calibration-cues/solve.py SCENE SIGHTINGS.npz [--speed-weight W]
        [--span FRAMES]

Residuals: the patch's head offsets (x, y per sighting, share of the person's pixel height), and per speed reading
(two sightings of one track ``--span`` to twice that many frames apart) the log of its ground speed over the track's
median, times 0.1 x ``--speed-weight``. A wrong focal length or tilt warps the ground, and a walker's speed then
changes along their path; the ratio needs no speed prior. Soft-L1, outliers dropped as in the patch, 20 resamples of
the tracks for the spread. Errors against the scene's own calibration.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from vc.calibration import from_people
from vc.scenes.loader import load_scene


def speed_pairs(tracks: np.ndarray, frames: np.ndarray, span: int) -> np.ndarray:
    pairs = []
    for track in np.unique(tracks):
        rows = np.flatnonzero(tracks == track)
        rows = rows[np.argsort(frames[rows])]
        for row in rows:
            later = rows[frames[rows] - frames[row] >= span]
            if len(later) and frames[later[0]] - frames[row] <= 2 * span:
                pairs.append((row, later[0], track))
    return np.array(pairs).reshape(-1, 3)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", type=Path)
    parser.add_argument("sightings", type=Path)
    parser.add_argument("--speed-weight", type=float, default=0.0)
    parser.add_argument("--span", type=int, default=12)
    args = parser.parse_args()
    camera = load_scene(args.scene).camera
    data = np.load(args.sightings)
    heads, feet, tracks, frames = data["heads"], data["feet"], data["tracks"], data["frames"]
    segment = (float(data["low"]), float(data["high"]))
    size, truth = camera.size, from_people.pose_of(camera)
    pairs = speed_pairs(tracks, frames, args.span)

    def speeds(params: np.ndarray, rows: np.ndarray) -> np.ndarray:
        model = from_people.camera_of(size, *params)
        ground = model.ground_from_pixels(feet, plane_z=segment[0])
        chosen = pairs[rows]
        distance = np.linalg.norm(ground.points[chosen[:, 1], :2] - ground.points[chosen[:, 0], :2], axis=1)
        ok = ground.ok[chosen[:, 0]] & ground.ok[chosen[:, 1]] & np.isfinite(distance) & (distance > 0)
        log_speed = np.log(np.where(ok, distance / (frames[chosen[:, 1]] - frames[chosen[:, 0]]), 1.0))
        out = np.ones(len(chosen))
        for track in np.unique(chosen[:, 2]):
            mine = (chosen[:, 2] == track) & ok
            if mine.sum() >= 2:
                out[mine] = log_speed[mine] - np.median(log_speed[mine])
        return out

    def residuals(params: np.ndarray, head_rows: np.ndarray, speed_rows: np.ndarray) -> np.ndarray:
        return np.r_[from_people._residuals(params, size, heads[head_rows], feet[head_rows], segment),
                     args.speed_weight * 0.1 * speeds(params, speed_rows)]

    def fit(head_rows: np.ndarray, speed_rows: np.ndarray, start: np.ndarray) -> np.ndarray:
        params = start
        for _ in range(2):
            offsets = np.abs(from_people._residuals(params, size, heads[head_rows], feet[head_rows], segment))
            worst = offsets.reshape(-1, 2).max(axis=1)
            median = np.median(worst)
            kept = head_rows[worst <= median + from_people.OUTLIER_MADS * 1.4826 * np.median(np.abs(worst - median))]
            params = least_squares(residuals, params, args=(kept, speed_rows), loss="soft_l1",
                                   f_scale=from_people.LOSS_SCALE, x_scale=np.array([size[0], 10.0, 5.0, 5.0]),
                                   bounds=from_people._bounds(size), method="trf").x
        return params

    every_head, every_speed = np.arange(len(heads)), np.arange(len(pairs))
    params = fit(every_head, every_speed, from_people._grid_start(size, heads, feet, segment))
    rng = np.random.default_rng(0)
    people = np.unique(tracks)
    draws = []
    for _ in range(20):
        chosen = rng.choice(people, len(people))
        head_rows = np.concatenate([np.flatnonzero(tracks == person) for person in chosen])
        speed_rows = np.concatenate([np.flatnonzero(pairs[:, 2] == person) for person in chosen])
        draws.append(fit(head_rows, speed_rows, params))
    spread = np.std(draws, axis=0)
    print(f"{len(heads)} sightings, {len(people)} tracks, {len(pairs)} speed readings; speed weight "
          f"{args.speed_weight}, span {args.span}: focal {100 * (params[0] / truth['focal_px'] - 1):+.1f} % "
          f"(+-{100 * spread[0] / truth['focal_px']:.0f}), tilt {params[1] - truth['tilt_deg']:+.2f} deg "
          f"(+-{spread[1]:.1f}), roll {params[2] - truth['roll_deg']:+.2f} deg, height "
          f"{100 * (params[3] / truth['height_m'] - 1):+.1f} % (+-{100 * spread[3] / truth['height_m']:.0f})")


if __name__ == "__main__":
    main()
