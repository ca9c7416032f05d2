"""A camera from what an installer has: image points whose ground positions were measured, or an image <-> ground
homography (as the ETH and UCY pedestrian sets ship ``H.txt``).

Both are a plane seen through a pinhole, so both go through the ground -> image homography
``H ~ K [r1 r2 t]`` (Zhang, "A flexible new technique for camera calibration", PAMI 2000, section 2.3):

1. ``H`` is fitted to the points (OpenCV's direct linear transform) or read from the file (the file maps image
   pixels to ground metres, ETH/UCY's direction, and is inverted).
2. The focal length, when not given, is the one that makes ``K^-1 H``'s first two columns orthogonal and of equal
   length, with square pixels, no skew and the principal point at the image centre: two linear equations in
   ``1 / f^2``, solved in the least-squares sense. A camera looking straight down leaves ``f`` unobservable (the
   equations vanish): the focal length must then be given.
3. The pose follows from the columns (scaled to unit length, the sign that puts the points in front of the
   camera, ``r3 = r1 x r2``, the nearest rotation). A solution with the camera below the ground means the ground
   axes were given mirrored (they must be right-handed seen from above, z up) and is refused.
4. From points, the focal length and pose are then refined by least squares on the reprojection error
   (scipy's ``least_squares``) and every point's error is reported.

Lens distortion stays zero: four to eight points cannot tell it from the pose. Ground coordinates are in
``units`` (metres by default) and the camera comes out in metres, like every reader of :mod:`.readers`. Bad input
(fewer than four points, collinear points, NaN, points off the image, a singular homography, a solution that
puts the camera below the ground or the points behind it) raises :class:`vc.errors.InputError` naming the file.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from scipy.optimize import least_squares

from vc.calibration.camera import Camera
from vc.errors import InputError

MIN_POINTS = 4
#: Points whose spread across their second direction is below this share of the first are collinear.
COLLINEAR_RATIO = 0.01
#: A homography whose smallest singular value is below this share of its largest is singular.
SINGULAR_RATIO = 1e-9


@dataclass(frozen=True)
class GroundCalibration:
    """A camera solved from measured ground points, with each point's reprojection error."""

    camera: Camera
    image_points: np.ndarray  # (N, 2) px
    ground_points: np.ndarray  # (N, 2) m
    errors_px: np.ndarray  # (N,) reprojection error of each point
    focal_solved: bool  # False: the focal length was given

    @property
    def camera_height_m(self) -> float:
        return float(self.camera.center[2])

    def to_dict(self) -> dict:
        return {"focal_px": round(float(self.camera.fx), 3), "focal_solved": self.focal_solved,
                "camera_height_m": round(self.camera_height_m, 3),
                "reprojection_px": {"median": round(float(np.median(self.errors_px)), 3),
                                    "max": round(float(self.errors_px.max()), 3)},
                "points": [{"image_px": [round(float(v), 2) for v in uv], "ground_m": [round(float(v), 3) for v in xy],
                            "error_px": round(float(error), 3)}
                           for uv, xy, error in zip(self.image_points, self.ground_points, self.errors_px,
                                                    strict=True)]}


def read_ground_points(path: Path, units_scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Image points (N, 2) and ground points (N, 2, metres) from a CSV of ``u, v, x, y`` rows (pixels, then
    ground coordinates in the file's units). A first row that is not numbers is a header; ``#`` starts a comment."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "", "ground points file not found")
    rows, header_allowed = [], True
    with path.open(newline="") as handle:
        for number, row in enumerate(csv.reader(handle), start=1):
            cells = [cell.strip() for cell in row]
            if not cells or not any(cells) or cells[0].startswith("#"):
                continue
            if len(cells) < 4:
                raise InputError(path, f"line {number}", f"expected u, v, x, y, got {len(cells)} values")
            try:
                values = [float(cell) for cell in cells[:4]]
            except ValueError:
                if header_allowed:
                    header_allowed = False
                    continue  # the first row that is not a comment may name the columns
                raise InputError(path, f"line {number}", f"not a number in {', '.join(cells[:4])}") from None
            if not np.isfinite(values).all():
                raise InputError(path, f"line {number}", "not finite (NaN or inf)")
            rows.append(values)
            header_allowed = False
    points = np.array(rows, np.float64).reshape(-1, 4)
    return points[:, :2], points[:, 2:] * units_scale


def read_homography(path: Path) -> np.ndarray:
    """A 3x3 image -> ground homography (ETH/UCY ``H.txt``: nine numbers, whitespace or commas between them)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "", "homography file not found")
    try:
        values = np.array([float(v) for v in path.read_text().replace(",", " ").split()], np.float64)
    except ValueError:
        raise InputError(path, "", "not a homography: every value must be a number") from None
    if values.size != 9:
        raise InputError(path, "", f"a homography has 9 values, the file has {values.size}")
    if not np.isfinite(values).all():
        raise InputError(path, "", "the homography contains NaN or inf")
    return values.reshape(3, 3)


def _check_spread(points: np.ndarray, path: Path | None, what: str) -> None:
    centred = points - points.mean(axis=0)
    spread = np.linalg.svd(centred, compute_uv=False)
    if spread[0] == 0 or spread[1] < COLLINEAR_RATIO * spread[0]:
        raise InputError(path, "", f"the {what} are (nearly) collinear: points along one line do not fix a "
                                   f"camera; add points off that line")


def _focal_from_homography(h: np.ndarray, path: Path | None) -> float:
    """Zhang's constraints with the principal point at the origin of ``h``'s image side (see the docstring)."""
    (h11, h12, _), (h21, h22, _), (h31, h32, _) = h
    a = np.array([h11 * h12 + h21 * h22, h11**2 + h21**2 - h12**2 - h22**2])
    b = np.array([h31 * h32, h31**2 - h32**2])
    denominator = float(a @ a)
    inverse_square = -float(a @ b) / denominator if denominator > 0 else 0.0
    if not np.isfinite(inverse_square) or inverse_square <= 0:
        raise InputError(path, "focal_px", "cannot solve the focal length from this view (a camera looking straight "
                                           "down, or points too few or too close together): give focal_px")
    return 1.0 / np.sqrt(inverse_square)


def intrinsics(width: int, height: int, focal_px: float) -> np.ndarray:
    """Square pixels, no skew, the principal point at the image centre."""
    return np.array([[focal_px, 0.0, (width - 1) / 2], [0.0, focal_px, (height - 1) / 2], [0.0, 0.0, 1.0]])


def camera_from_homography(ground_to_image: np.ndarray, size: tuple[int, int], focal_px: float | None = None,
                           path: Path | None = None, ground_points: np.ndarray | None = None) -> Camera:
    """The pinhole camera (no distortion) whose view of the ground is ``ground_to_image`` (steps 2 and 3 of the
    module docstring). ``ground_points`` (N, 2), when given, must lie in front of it; otherwise the ground under
    the image's bottom centre must."""
    width, height = size
    h = np.asarray(ground_to_image, np.float64)
    singular = np.linalg.svd(h, compute_uv=False)
    if not np.isfinite(h).all() or singular[-1] <= SINGULAR_RATIO * singular[0]:
        raise InputError(path, "", "the homography is singular: it does not map a plane onto the image")
    to_centre = np.array([[1.0, 0.0, -(width - 1) / 2], [0.0, 1.0, -(height - 1) / 2], [0.0, 0.0, 1.0]])
    focal = float(focal_px) if focal_px is not None else _focal_from_homography(to_centre @ h, path)
    m = np.linalg.inv(intrinsics(width, height, focal)) @ h
    scale = 2.0 / (np.linalg.norm(m[:, 0]) + np.linalg.norm(m[:, 1]))
    probe = np.asarray(ground_points if ground_points is not None else [[0.0, 0.0]], np.float64)
    depth = (scale * m @ np.c_[probe, np.ones(len(probe))].T)[2]
    if ground_points is None:
        bottom = np.linalg.inv(h) @ np.array([(width - 1) / 2, height - 1.0, 1.0])
        depth = np.array([scale * (m @ bottom)[2] * np.sign(bottom[2])])
    sign = 1.0 if np.median(depth) > 0 else -1.0
    r1, r2, t = sign * scale * m[:, 0], sign * scale * m[:, 1], sign * scale * m[:, 2]
    u, _, vt = np.linalg.svd(np.column_stack([r1, r2, np.cross(r1, r2)]))
    rotation = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    camera = Camera(width, height, intrinsics(width, height, focal), rotation, t)
    if camera.center[2] <= 0:
        raise InputError(path, "", f"the solution puts the camera {-camera.center[2]:.2f} m below the ground: the "
                                   "ground axes are probably mirrored (x, y must be right-handed seen from above)")
    if ground_points is not None and not camera.project(np.c_[probe, np.zeros(len(probe))]).in_front.all():
        raise InputError(path, "", "no camera sees every point in front of it: check the points' pairing")
    if ground_points is None and not camera.ground_from_pixels(np.array([[(width - 1) / 2, height - 1.0]])).ok[0]:
        raise InputError(path, "", "the homography puts the bottom of the image above the horizon: it does not "
                                   "map this image onto the ground")
    return camera


def reprojection_residuals(camera: Camera, image: np.ndarray, ground: np.ndarray) -> np.ndarray:
    """Each ground point's projection minus its pixel (N, 2); 1e6 where the camera cannot see it."""
    projected = camera.project(np.c_[ground, np.zeros(len(ground))])
    return np.where(projected.ok[:, None], projected.uv - image, 1e6)


def check_points(image: np.ndarray, ground: np.ndarray, size: tuple[int, int], minimum: int,
                 path: Path | None) -> tuple[np.ndarray, np.ndarray]:
    """``image`` (N, 2 px) and ``ground`` (N, 2 m) as float arrays, or InputError naming ``path`` when there are
    fewer than ``minimum`` of them, one is not finite or one lies outside the image of ``size``."""
    image, ground = np.asarray(image, np.float64).reshape(-1, 2), np.asarray(ground, np.float64).reshape(-1, 2)
    width, height = size
    if len(image) < minimum:
        raise InputError(path, "", f"needs at least {minimum} points, got {len(image)}")
    if not (np.isfinite(image).all() and np.isfinite(ground).all()):
        raise InputError(path, "", "a point is not finite (NaN or inf)")
    outside = np.nonzero((image[:, 0] < -0.5) | (image[:, 0] > width - 0.5) | (image[:, 1] < -0.5)
                         | (image[:, 1] > height - 0.5))[0]
    if len(outside):
        raise InputError(path, f"point {outside[0] + 1}", f"({image[outside[0], 0]:g}, {image[outside[0], 1]:g}) "
                                                          f"lies outside the {width}x{height} image")
    return image, ground


def calibrate_from_ground_points(image: np.ndarray, ground: np.ndarray, size: tuple[int, int],
                                 focal_px: float | None = None, path: Path | None = None) -> GroundCalibration:
    """Solve the camera from ``image`` (N, 2 px) <-> ``ground`` (N, 2 m) pairs (see the module docstring)."""
    image, ground = check_points(image, ground, size, MIN_POINTS, path)
    width, height = size
    _check_spread(ground, path, "ground points")
    _check_spread(image, path, "image points")
    homography, _ = cv2.findHomography(ground, image, 0)
    if homography is None:
        raise InputError(path, "", "no homography fits these points (check their pairing)")
    camera = camera_from_homography(homography, size, focal_px, path, ground)

    def unpack(parameters: np.ndarray) -> Camera:
        focal = focal_px if focal_px is not None else float(np.exp(parameters[6]))
        rotation = cv2.Rodrigues(parameters[:3].reshape(3, 1))[0]
        return Camera(width, height, intrinsics(width, height, focal), rotation, parameters[3:6])

    start = np.r_[cv2.Rodrigues(camera.R)[0].ravel(), camera.t, [] if focal_px is not None else [np.log(camera.fx)]]
    fit = least_squares(lambda p: reprojection_residuals(unpack(p), image, ground).ravel(), start, method="lm"
                        if 2 * len(image) >= len(start) else "trf")
    refined = unpack(fit.x)
    if refined.center[2] <= 0 or not refined.project(np.c_[ground, np.zeros(len(ground))]).in_front.all():
        refined = camera  # the refinement wandered off; the closed form stands
    errors = np.linalg.norm(reprojection_residuals(refined, image, ground), axis=1)
    return GroundCalibration(refined, image, ground, errors, focal_px is None)


def write_opencv_yaml(camera: Camera, path: Path) -> None:
    """The camera as an OpenCV ``cv::FileStorage`` YAML (``camera_matrix``, ``distortion_coefficients``, ``R``,
    ``t``, image size), as :func:`vc.calibration.readers.read_opencv` reads it back. Zero distortion only."""
    if not camera.distortion.is_identity:
        raise ValueError("only a camera without lens distortion is written as OpenCV YAML here")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.partial.yaml")
    storage = cv2.FileStorage(str(temporary), cv2.FILE_STORAGE_WRITE)
    if not storage.isOpened():
        raise OSError(f"cannot open {temporary} for writing")
    try:
        storage.write("image_width", camera.width)
        storage.write("image_height", camera.height)
        storage.write("camera_matrix", camera.K)
        storage.write("distortion_coefficients", np.zeros((1, 5)))
        storage.write("R", camera.R)
        storage.write("t", camera.t.reshape(3, 1))
    finally:
        storage.release()
    temporary.replace(path)


def statures_m(camera: Camera, boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The height (m) of a person standing upright in each box (N, 4: x0, y0, x1, y1, outer edges): feet at the
    box's bottom centre on the ground, head at its top centre, the head's ray taken where it passes closest to
    the vertical through the feet (lens distortion included). Returns heights and ``ok`` (False, NaN: feet above
    the horizon or a head ray parallel to the vertical)."""
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    middle = (boxes[:, 0] + boxes[:, 2]) / 2 - 0.5  # outer edges -> pixel centres
    feet = camera.ground_from_pixels(np.column_stack([middle, boxes[:, 3] - 0.5]))
    rays, head_ok = camera.unproject(np.column_stack([middle, boxes[:, 1] - 0.5]))
    towards_feet = feet.points - camera.center
    along = np.einsum("ij,ij->i", rays, towards_feet)
    with np.errstate(invalid="ignore", divide="ignore"):
        heights = (rays[:, 2] * along - towards_feet[:, 2]) / (1.0 - rays[:, 2] ** 2)
    ok = feet.ok & head_ok & np.isfinite(heights) & (np.abs(rays[:, 2]) < 1.0 - 1e-9)
    return np.where(ok, heights, np.nan), ok
