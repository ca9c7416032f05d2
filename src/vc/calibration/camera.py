"""One ``Camera`` type for every calibration the project reads.

Conventions (docs/design.md, one place each):

* World: metres, right-handed, z up, ground plane z = 0.
* Camera frame: OpenCV (x right, y down, z forward); ``R``, ``t`` map world -> camera: ``Xc = R Xw + t``.
* Pixels: OpenCV, the centre of the top-left pixel is (0, 0).

A pixel is ``K @ distort(x / z, y / z)``: the distortion model works on normalised coordinates, so Brown–Conrady
and Tsai cameras share everything else. Operations that can fail on some inputs (points behind the camera,
rays that never meet the ground, points outside the distortion model's domain) return a boolean ``ok`` array
next to the values and put NaN in the failed entries — never a silently wrong number.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np

from vc.calibration.distortion import Distortion, NoDistortion, distortion_from_dict

#: Points closer than this to the camera plane (metres along the optical axis) count as behind the camera.
MIN_DEPTH = 1e-6
#: Rays whose vertical direction component is below this are treated as parallel to the ground.
MIN_RAY_SLOPE = 1e-9


class Projection(NamedTuple):
    """Pixels of projected points; ``ok`` is False (and ``uv`` NaN) where a point cannot be imaged."""

    uv: np.ndarray
    in_front: np.ndarray
    in_domain: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        return self.in_front & self.in_domain


class GroundHit(NamedTuple):
    """Ground points (z = 0) seen through pixels; ``ok`` is False where the ray misses the ground."""

    points: np.ndarray
    ok: np.ndarray


@dataclass(frozen=True)
class Camera:
    """A calibrated camera: image size, intrinsics, distortion and world -> camera pose."""

    width: int
    height: int
    K: np.ndarray
    R: np.ndarray
    t: np.ndarray
    distortion: Distortion = field(default_factory=NoDistortion)

    def __post_init__(self) -> None:
        K = np.asarray(self.K, dtype=np.float64).reshape(3, 3)
        R = np.asarray(self.R, dtype=np.float64).reshape(3, 3)
        t = np.asarray(self.t, dtype=np.float64).reshape(3)
        if self.width <= 0 or self.height <= 0:
            raise ValueError(f"image size must be positive, got {self.width}x{self.height}")
        if not (np.isfinite(K).all() and np.isfinite(R).all() and np.isfinite(t).all()):
            raise ValueError("camera matrices contain NaN or inf")
        if K[0, 0] <= 0 or K[1, 1] <= 0:
            raise ValueError(f"focal lengths must be positive, got fx={K[0, 0]}, fy={K[1, 1]}")
        if not np.allclose(K[2], [0.0, 0.0, 1.0]) or K[1, 0] != 0.0:
            raise ValueError("K must be upper triangular with last row [0, 0, 1]")
        if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
            raise ValueError("R must be a rotation matrix (orthonormal, det +1)")
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "t", t)

    # --- intrinsics --------------------------------------------------------------------------------------------
    @property
    def size(self) -> tuple[int, int]:
        return (self.width, self.height)

    @property
    def fx(self) -> float:
        return float(self.K[0, 0])

    @property
    def fy(self) -> float:
        return float(self.K[1, 1])

    @property
    def cx(self) -> float:
        return float(self.K[0, 2])

    @property
    def cy(self) -> float:
        return float(self.K[1, 2])

    @property
    def center(self) -> np.ndarray:
        """Camera centre in world coordinates."""
        return -self.R.T @ self.t

    def pixels_from_normalised(self, xy: np.ndarray) -> np.ndarray:
        K = self.K
        u = K[0, 0] * xy[..., 0] + K[0, 1] * xy[..., 1] + K[0, 2]
        v = K[1, 1] * xy[..., 1] + K[1, 2]
        return np.stack([u, v], axis=-1)

    def normalised_from_pixels(self, uv: np.ndarray) -> np.ndarray:
        K = self.K
        y = (uv[..., 1] - K[1, 2]) / K[1, 1]
        x = (uv[..., 0] - K[0, 2] - K[0, 1] * y) / K[0, 0]
        return np.stack([x, y], axis=-1)

    # --- projection --------------------------------------------------------------------------------------------
    def world_to_camera(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) @ self.R.T + self.t

    def project(self, points: np.ndarray) -> Projection:
        """World points (..., 3) -> pixels (..., 2), with lens distortion."""
        pc = self.world_to_camera(points)
        z = pc[..., 2]
        in_front = np.isfinite(pc).all(axis=-1) & (z > MIN_DEPTH)
        safe_z = np.where(in_front, z, 1.0)
        normalised = pc[..., :2] / safe_z[..., None]
        distorted, in_domain = self.distortion.distort(np.where(in_front[..., None], normalised, 0.0))
        uv = self.pixels_from_normalised(distorted)
        uv[~(in_front & in_domain)] = np.nan
        return Projection(uv, in_front, in_domain)

    def unproject(self, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixels (..., 2) -> unit ray directions in world coordinates (..., 3), and ``ok``."""
        normalised, ok = self.distortion.undistort(self.normalised_from_pixels(np.asarray(uv, np.float64)))
        rays_cam = np.concatenate([normalised, np.ones(normalised.shape[:-1] + (1,))], axis=-1)
        rays = rays_cam @ self.R  # R.T applied to row vectors
        rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
        return rays, ok

    def ground_from_pixels(self, uv: np.ndarray, plane_z: float = 0.0) -> GroundHit:
        """Intersect the rays through ``uv`` with the horizontal plane z = ``plane_z``.

        A ray misses (``ok`` False) when undistortion fails, when it is parallel to the plane, or when the
        plane lies behind the camera along it (a pixel above the horizon).
        """
        rays, ok = self.unproject(uv)
        origin = self.center
        dz = rays[..., 2]
        with np.errstate(invalid="ignore", divide="ignore"):
            s = (plane_z - origin[2]) / np.where(np.abs(dz) > MIN_RAY_SLOPE, dz, np.nan)
        hit = ok & np.isfinite(s) & (s > 0)
        points = origin + np.where(hit, s, np.nan)[..., None] * rays
        return GroundHit(points, hit)

    def is_in_image(self, uv: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Whether pixels lie within the image (pixel centres from 0 to size - 1, extended by ``margin``)."""
        uv = np.asarray(uv)
        with np.errstate(invalid="ignore"):
            return (
                (uv[..., 0] >= -0.5 - margin)
                & (uv[..., 0] <= self.width - 0.5 + margin)
                & (uv[..., 1] >= -0.5 - margin)
                & (uv[..., 1] <= self.height - 0.5 + margin)
            )

    def person_pixel_height(self, feet: np.ndarray, height_m: float | np.ndarray) -> np.ndarray:
        """Image distance between the feet (on the ground) and a head ``height_m`` above them; NaN if unseen."""
        feet = np.asarray(feet, dtype=np.float64)
        heads = feet.copy()
        heads[..., 2] = feet[..., 2] + height_m
        foot_px, head_px = self.project(feet), self.project(heads)
        return np.linalg.norm(foot_px.uv - head_px.uv, axis=-1)

    def person_height_at_centres(self, uv: np.ndarray, height_m: float) -> np.ndarray:
        """Pixel height of a ``height_m`` person standing upright whose centre (half the stature above the feet)
        is seen at ``uv`` (..., 2); NaN where no such person can stand (rays above the centre plane's horizon)."""
        hit = self.ground_from_pixels(uv, plane_z=height_m / 2)
        feet = hit.points.copy()
        feet[..., 2] = 0.0
        return np.where(hit.ok, self.person_pixel_height(feet, height_m), np.nan)

    def horizon_pixels(self, samples: int = 721) -> np.ndarray:
        """Pixels of the horizon (vanishing points of horizontal directions), ordered by azimuth, (M, 2).

        Only the directions in front of the camera and inside the distortion model's domain are returned, so
        the result may be empty (a camera looking straight down has no horizon in view).
        """
        azimuth = np.linspace(-np.pi, np.pi, samples)
        directions = np.stack([np.cos(azimuth), np.sin(azimuth), np.zeros_like(azimuth)], axis=-1)
        dc = directions @ self.R.T
        ahead = dc[:, 2] > 1e-9
        normalised = dc[ahead, :2] / dc[ahead, 2:3]
        distorted, ok = self.distortion.distort(normalised)
        return self.pixels_from_normalised(distorted[ok])

    # --- image geometry under resize and crop ------------------------------------------------------------------
    def cropped(self, x0: float, y0: float, width: int, height: int) -> Camera:
        """The camera of the sub-image whose top-left pixel is pixel (x0, y0) of this one."""
        K = self.K.copy()
        K[0, 2] -= x0
        K[1, 2] -= y0
        return replace(self, width=int(width), height=int(height), K=K)

    def resized(self, width: int, height: int) -> Camera:
        """The camera of this image resampled to ``width`` x ``height``.

        With pixel centres at integers, the edges of the image sit at -0.5 and size - 0.5, so a pixel maps as
        ``u' = s (u + 0.5) - 0.5``: the principal point moves by that rule, the focal length scales by ``s``.
        """
        sx, sy = width / self.width, height / self.height
        K = self.K.copy()
        K[0, 0] *= sx
        K[0, 1] *= sx
        K[1, 1] *= sy
        K[0, 2] = sx * (K[0, 2] + 0.5) - 0.5
        K[1, 2] = sy * (K[1, 2] + 0.5) - 0.5
        return replace(self, width=int(width), height=int(height), K=K)

    # --- serialisation -----------------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """The inline form of the scene YAML (``camera:``), which :func:`camera_from_dict` reads back."""
        return {
            "size": [self.width, self.height],
            "K": self.K.tolist(),
            "distortion": self.distortion.to_dict(),
            "R": self.R.tolist(),
            "t": self.t.tolist(),
        }


def camera_from_dict(spec: dict) -> Camera:
    width, height = spec["size"]
    return Camera(
        width=int(width),
        height=int(height),
        K=np.asarray(spec["K"], dtype=np.float64),
        R=np.asarray(spec["R"], dtype=np.float64),
        t=np.asarray(spec["t"], dtype=np.float64),
        distortion=distortion_from_dict(spec.get("distortion") or {"model": "none"}),
    )


def rotation_xyz(rx: float, ry: float, rz: float) -> np.ndarray:
    """``Rz(rz) @ Ry(ry) @ Rx(rx)`` with right-handed elementary rotations (Tsai's convention)."""
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def rotation_from_quaternion(x: float, y: float, z: float, w: float) -> np.ndarray:
    q = np.array([x, y, z, w], dtype=np.float64)
    n = np.linalg.norm(q)
    if not np.isfinite(n) or n < 1e-12:
        raise ValueError("rotation quaternion has zero length")
    x, y, z, w = q / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def look_at(eye: np.ndarray, target: np.ndarray, roll_deg: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """World -> camera (R, t) for a camera at ``eye`` looking at ``target`` with z-up world, image y down."""
    eye, target = np.asarray(eye, np.float64), np.asarray(target, np.float64)
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-9:
        raise ValueError("look_at: viewing direction is vertical; the image x axis is undefined")
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    R = np.stack([x, y, z])
    if roll_deg:
        a = np.radians(roll_deg)
        roll = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
        R = roll @ R
    return R, -R @ eye
