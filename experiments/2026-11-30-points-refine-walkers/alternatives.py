"""The two ways of combining points and people that were tried before the prior and not kept (decision 0030):

1. a joint fit of the points and every sighting (each head's residual beside each point's reprojection error);
2. the people's camera scaled by a distance measured between two points.

    PYTHONPATH=. python experiments/2026-11-30-points-refine-walkers/alternatives.py

PETS09's people of dev frames 1-400 every 2nd (as ``vc-scene init --frames 1:400:2``), its eight measured features
exact, against the Tsai calibration. Prints the errors (results/alternatives.txt holds this run's).
"""

from __future__ import annotations

import itertools
import math

import cv2
import numpy as np
from run import PETS, VIDEO, errors  # this folder's run.py
from scipy.optimize import least_squares

from vc.calibration.camera import Camera
from vc.calibration.from_people import LOSS_SCALE, OUTLIER_MADS, pose_of, predicted_heads, solve
from vc.calibration.ground_points import (
    calibrate_from_ground_points,
    intrinsics,
    read_ground_points,
    reprojection_residuals,
    statures_m,
)
from vc.calibration.points_and_people import POINT_SIGMA_PX
from vc.calibration.walkers import walkers_in_video
from vc.deploy.frames import FrameRange
from vc.scenes.background import median_background
from vc.scenes.loader import load_scene


def joint_fit(fit, heads: np.ndarray, feet: np.ndarray, tracks: np.ndarray) -> Camera:
    """The points and every sighting in one least squares; the stature free; each person weighs as one sighting."""
    size = fit.camera.size
    boxes = np.c_[feet[:, 0] - 0.5, heads[:, 1] + 0.5, feet[:, 0] + 1.5, feet[:, 1] + 0.5]
    stature, ok = statures_m(fit.camera, boxes)
    median = np.nanmedian(stature)
    kept = ok & (np.abs(stature - median) <= OUTLIER_MADS * 1.4826 * np.nanmedian(np.abs(stature - median)))
    _, person = np.unique(tracks[kept], return_inverse=True)
    weight = 1.0 / np.sqrt(np.bincount(person)[person])
    heads, feet = heads[kept], feet[kept]

    def unpack(p: np.ndarray) -> Camera:
        return Camera(size[0], size[1], intrinsics(size[0], size[1], math.exp(p[6])),
                      cv2.Rodrigues(p[:3].reshape(3, 1))[0], p[3:6])

    def residuals(p: np.ndarray) -> np.ndarray:
        camera = unpack(p)
        points = reprojection_residuals(camera, fit.image_points, fit.ground_points) / POINT_SIGMA_PX
        predicted, seen = predicted_heads(camera, feet, p[7])
        offset = (heads - predicted) / np.maximum(np.linalg.norm(heads - feet, axis=1), 1.0)[:, None]
        offset[~seen] = 1.0
        return np.r_[points.ravel(), (offset / LOSS_SCALE * weight[:, None]).ravel()]

    start = np.r_[cv2.Rodrigues(fit.camera.R)[0].ravel(), fit.camera.t, math.log(fit.camera.fx), median]
    return unpack(least_squares(residuals, start, loss="soft_l1", f_scale=1.0, method="trf").x)


def main() -> None:
    frames = FrameRange(1, 400, 2)
    background = median_background(VIDEO, progress=False, frames=frames).image
    sightings = walkers_in_video(VIDEO, background, frames, False)
    heads, feet = np.array([s.head for s in sightings]), np.array([s.foot for s in sightings])
    tracks = np.array([s.track for s in sightings])
    truth = pose_of(load_scene(PETS / "scene.yaml").camera)
    image, ground = read_ground_points(PETS / "ground_points.csv")
    fit = calibrate_from_ground_points(image, ground, (background.shape[1], background.shape[0]))
    print("eight points alone: focal {:+.1f} %, tilt {:+.2f}, height {:+.1f} %".format(*errors(fit.camera, truth)))
    print("eight points and every sighting: focal {:+.1f} %, tilt {:+.2f}, height {:+.1f} %".format(
        *errors(joint_fit(fit, heads, feet, tracks), truth)))
    people = solve(heads, feet, tracks, fit.camera.size, bootstrap=0)
    heights = []
    for i, j in itertools.combinations(range(len(image)), 2):
        seen = people.camera.ground_from_pixels(image[[i, j]]).points[:, :2]
        scale = np.linalg.norm(ground[i] - ground[j]) / np.linalg.norm(seen[0] - seen[1])
        heights.append(100 * (people.height_m * scale / truth["height_m"] - 1))
    print(f"the people's camera scaled by one measured distance (28 pairs): height median {np.median(heights):+.1f} %, "
          f"range {min(heights):+.1f} to {max(heights):+.1f} %")


if __name__ == "__main__":
    main()
