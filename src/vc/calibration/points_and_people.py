"""A camera from measured ground points and the people walking through the view together: the points win where
they are given, and refine the people's camera (issue 60; decision 0030).

The people (:mod:`.from_people`) tell the focal length, tilt and roll, and the camera's height only as a multiple
of a stature prior; they say nothing of where the ground's axes are. Measured points tell the ground's axes and
scale exactly and the rest only as well as their spread allows: four points close together, or a pixel off, often
leave the focal length free (a third of noisy four-point sets of PETS09's eight features cannot be solved at all).
The two are combined as a measurement and a prior:

    minimise   sum over points  |projection of the point - its pixel|^2 / POINT_SIGMA_PX^2
             + sum over (focal, tilt, roll, height)  (value - the people's value)^2 / the people's spread^2

The people's spread is their bootstrap spread, the height's widened by :data:`STATURE_SPREAD` (the uncertainty of
the stature prior itself, which resampling the people cannot show), each floored at :data:`MIN_SPREAD`. Where the
points determine a parameter, they win; where they leave it free, the people's value stands. Two points suffice
(four equations and the four prior terms for seven unknowns: rotation, position, focal length). A focal length the
user gave is held, as everywhere.

The fit starts from the people's camera turned and shifted in the ground plane onto the points (the rigid 2-D
transform that best maps where that camera sees the points' pixels onto their measured positions; Kabsch), and,
with four or more points, also from the points' own solution (:func:`calibrate_from_ground_points`); the better
end point is kept.
"""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np
from scipy.optimize import least_squares

from vc.calibration.camera import Camera
from vc.calibration.from_people import PARAMETERS, PeopleCalibration, pose_of
from vc.calibration.ground_points import (
    MIN_POINTS,
    GroundCalibration,
    calibrate_from_ground_points,
    check_points,
    intrinsics,
    reprojection_residuals,
)
from vc.errors import InputError

#: Points needed beside the people: two fix the ground's axes and scale.
MIN_POINTS_WITH_PEOPLE = 2
#: A measured point's error in the image, the click and the tape together (px).
POINT_SIGMA_PX = 1.5
#: The uncertainty of the mean stature of the people in view as a share of it: the 1.70 m prior against adults'
#: means of 1.64-1.78 m by sex and country (NCD-RisC, eLife 2016; see :data:`.from_people.STATURE_M`).
STATURE_SPREAD = 0.03
#: The people's spreads are floored at these (focal share, degrees, degrees, height share): resampling the people
#: shows their random error, not the model's (no lens, a stature prior, blobs' ends), so a tight bootstrap must
#: still yield to the points. The floors are the solve's median error with eight people drawn through a known
#: camera (3.5 %, 0.7 degrees and 6 % in experiments/2026-11-30-where-walker-calibration-fails; roll 0.5).
MIN_SPREAD = (0.035, 0.7, 0.5, 0.06)


def people_prior(people: PeopleCalibration) -> tuple[np.ndarray, np.ndarray]:
    """The people's (focal, tilt, roll, height) and the spread each is trusted to (see the module docstring)."""
    values = np.array([people.focal_px, people.tilt_deg, people.roll_deg, people.height_m])
    spread = np.array([people.spread.get(name, 0.0) for name in PARAMETERS])
    spread[3] = math.hypot(spread[3], STATURE_SPREAD * people.height_m)
    floor = np.array(MIN_SPREAD) * np.array([people.focal_px, 1.0, 1.0, people.height_m])
    return values, np.maximum(spread, floor)


def _pose_vector(camera: Camera) -> np.ndarray:
    pose = pose_of(camera)
    return np.array([pose[name] for name in PARAMETERS])


def people_camera_on_points(people: PeopleCalibration, image: np.ndarray, ground: np.ndarray) -> Camera | None:
    """The people's camera turned about the vertical and shifted so that the ground it sees through the points'
    pixels best matches their measured positions (Kabsch in the plane); None when it sees fewer than two of them
    on the ground."""
    hit = people.camera.ground_from_pixels(image)
    if hit.ok.sum() < MIN_POINTS_WITH_PEOPLE:
        return None
    seen, measured = hit.points[hit.ok, :2], ground[hit.ok]
    u, _, vt = np.linalg.svd((seen - seen.mean(axis=0)).T @ (measured - measured.mean(axis=0)))
    turn = (u @ np.diag([1.0, np.sign(np.linalg.det(u @ vt))]) @ vt).T
    to_points = np.eye(3)
    to_points[:2, :2] = turn
    shift = np.r_[measured.mean(axis=0) - turn @ seen.mean(axis=0), 0.0]  # measured = to_points @ seen + shift
    rotation = people.camera.R @ to_points.T
    return Camera(people.camera.width, people.camera.height, people.camera.K, rotation,
                  people.camera.t - rotation @ shift)


def calibrate_from_points_and_people(image: np.ndarray, ground: np.ndarray, people: PeopleCalibration,
                                     path: Path | None = None) -> GroundCalibration:
    """The camera that best explains the measured ``image`` (N, 2 px) <-> ``ground`` (N, 2 m) points and agrees
    with ``people``'s solution within its spread (see the module docstring); InputError naming ``path`` for fewer
    than two points, points off the image, or two points at one place."""
    size = people.camera.size
    image, ground = check_points(image, ground, size, MIN_POINTS_WITH_PEOPLE, path)
    if np.ptp(ground, axis=0).max() <= 0 or np.ptp(image, axis=0).max() <= 0:
        raise InputError(path, "", "the points are all at one place: they give no direction or scale")
    prior, spread = people_prior(people)
    focal_given = people.focal_px if people.focal_given else None
    starts = [camera for camera in [people_camera_on_points(people, image, ground)] if camera is not None]
    if len(image) >= MIN_POINTS:
        try:
            starts.append(calibrate_from_ground_points(image, ground, size, focal_given, path).camera)
        except InputError:
            pass  # too few or too close to solve alone: the people's start carries the fit
    if not starts:
        raise InputError(path, "", "the people's camera sees none of these points on the ground, and they are too "
                                   "few to solve the camera alone: check the points' pairing")

    def unpack(parameters: np.ndarray) -> Camera:
        focal = focal_given if focal_given is not None else math.exp(parameters[6])
        rotation = cv2.Rodrigues(parameters[:3].reshape(3, 1))[0]
        return Camera(size[0], size[1], intrinsics(size[0], size[1], focal), rotation, parameters[3:6])

    def residuals(parameters: np.ndarray) -> np.ndarray:
        camera = unpack(parameters)
        points = reprojection_residuals(camera, image, ground) / POINT_SIGMA_PX
        return np.r_[points.ravel(), (_pose_vector(camera) - prior) / spread]

    best = None
    for start in starts:
        vector = np.r_[cv2.Rodrigues(start.R)[0].ravel(), start.t, [] if focal_given else [math.log(start.fx)]]
        fit = least_squares(residuals, vector, method="trf")
        camera = unpack(fit.x)
        if camera.center[2] > 0 and (best is None or fit.cost < best[0]):
            best = (fit.cost, camera)
    if best is None:
        raise InputError(path, "", "no camera above the ground explains these points and the people: check the "
                                   "points' pairing and that x, y are right-handed seen from above")
    camera = best[1]
    errors = np.linalg.norm(reprojection_residuals(camera, image, ground), axis=1)
    return GroundCalibration(camera, image, ground, errors, focal_given is None)
