"""Lens distortion models, acting on normalised image coordinates (x/z, y/z).

Both models the project meets in the wild are here:

* :class:`BrownConrady` — OpenCV's (k1, k2, p1, p2, k3). Defined from *undistorted* to *distorted*
  coordinates, so ``distort`` is closed form and ``undistort`` is an iterative inversion.
* :class:`TsaiRadial` — Tsai's one-term radial model as used by the PETS calibration files. Defined the other
  way round (distorted to undistorted), so ``undistort`` is closed form and ``distort`` is the inversion.

Every method returns ``(points, ok)``: ``ok`` is False where a point lies outside the domain in which the model
is one-to-one, or where the inversion did not converge. Such points are NaN in the output, so a caller that
ignores the flag gets a loud NaN downstream rather than a silently wrong pixel.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

#: Newton iterations after which an inversion that has not converged is reported as failed.
MAX_ITERATIONS = 60
#: Convergence threshold in normalised coordinates (about 1e-9 px for a 1000 px focal length).
TOLERANCE = 1e-12


class Distortion(Protocol):
    """A lens distortion model in normalised coordinates; arrays are (..., 2)."""

    def distort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...

    def undistort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...

    @property
    def is_identity(self) -> bool: ...

    def to_dict(self) -> dict: ...


@dataclass(frozen=True)
class NoDistortion:
    """An ideal pinhole lens."""

    def distort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        xy = np.asarray(xy, dtype=np.float64)
        return xy.copy(), np.isfinite(xy).all(axis=-1)

    def undistort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.distort(xy)

    @property
    def is_identity(self) -> bool:
        return True

    def to_dict(self) -> dict:
        return {"model": "none"}


def _max_monotonic_radius(radial_derivative, r_limit: float = 10.0) -> float:
    """Smallest radius in (0, r_limit] where d(r * f(r))/dr stops being positive (r_limit if it never does).

    Beyond that radius the radial map folds back on itself: two undistorted radii land on one distorted radius
    and no inversion can be trusted, so points there are flagged instead of silently mapped.
    """
    r = np.linspace(0.0, r_limit, 200_001)
    bad = np.nonzero(radial_derivative(r) <= 0.0)[0]
    return float(r[bad[0] - 1]) if bad.size else float("inf")


@dataclass(frozen=True)
class BrownConrady:
    """OpenCV's radial-tangential model (k1, k2, p1, p2, k3), undistorted -> distorted."""

    k1: float = 0.0
    k2: float = 0.0
    p1: float = 0.0
    p2: float = 0.0
    k3: float = 0.0

    def __post_init__(self) -> None:
        k1, k2, k3 = self.k1, self.k2, self.k3
        # d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)], the radial part of the map.
        r_max = _max_monotonic_radius(lambda r: 1 + 3 * k1 * r**2 + 5 * k2 * r**4 + 7 * k3 * r**6)
        object.__setattr__(self, "max_undistorted_radius", r_max)

    @property
    def coefficients(self) -> tuple[float, float, float, float, float]:
        return (self.k1, self.k2, self.p1, self.p2, self.k3)

    @property
    def is_identity(self) -> bool:
        return not any(self.coefficients)

    def to_dict(self) -> dict:
        return {"model": "opencv", "k": list(self.coefficients)}

    def _forward(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r2 = x * x + y * y
        radial = 1 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3))
        xd = x * radial + 2 * self.p1 * x * y + self.p2 * (r2 + 2 * x * x)
        yd = y * radial + self.p1 * (r2 + 2 * y * y) + 2 * self.p2 * x * y
        return xd, yd

    def _jacobian(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        r2 = x * x + y * y
        radial = 1 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3))
        dradial_dr2 = self.k1 + r2 * (2 * self.k2 + 3 * self.k3 * r2)
        dxx = radial + 2 * x * x * dradial_dr2 + 2 * self.p1 * y + 6 * self.p2 * x
        dxy = 2 * x * y * dradial_dr2 + 2 * self.p1 * x + 2 * self.p2 * y
        dyx = 2 * x * y * dradial_dr2 + 2 * self.p1 * x + 2 * self.p2 * y
        dyy = radial + 2 * y * y * dradial_dr2 + 6 * self.p1 * y + 2 * self.p2 * x
        return dxx, dxy, dyx, dyy

    def distort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        xy = np.asarray(xy, dtype=np.float64)
        x, y = xy[..., 0], xy[..., 1]
        ok = np.isfinite(x) & np.isfinite(y) & (np.hypot(x, y) <= self.max_undistorted_radius)
        out = np.stack(self._forward(x, y), axis=-1)
        out[~ok] = np.nan
        return out, ok

    def undistort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Newton's method on the 2-D map, started at the distorted point itself."""
        xy = np.asarray(xy, dtype=np.float64)
        target_x, target_y = xy[..., 0], xy[..., 1]
        finite = np.isfinite(target_x) & np.isfinite(target_y)
        x = np.where(finite, target_x, 0.0)
        y = np.where(finite, target_y, 0.0)
        tx, ty = x.copy(), y.copy()
        converged = np.zeros(x.shape, dtype=bool)
        for _ in range(MAX_ITERATIONS):
            fx, fy = self._forward(x, y)
            ex, ey = fx - tx, fy - ty
            converged = np.hypot(ex, ey) <= TOLERANCE * (1.0 + np.hypot(tx, ty))
            if converged.all():
                break
            a, b, c, d = self._jacobian(x, y)
            det = a * d - b * c
            safe = np.abs(det) > 1e-15
            det = np.where(safe, det, 1.0)
            step_x = np.where(safe, (d * ex - b * ey) / det, 0.0)
            step_y = np.where(safe, (a * ey - c * ex) / det, 0.0)
            # Damp steps that would jump far: keeps Newton inside the basin on strong distortion.
            scale = np.minimum(1.0, 0.5 * (1.0 + np.hypot(x, y)) / np.maximum(np.hypot(step_x, step_y), 1e-300))
            x = x - step_x * scale
            y = y - step_y * scale
        ok = finite & converged & (np.hypot(x, y) <= self.max_undistorted_radius)
        out = np.stack([x, y], axis=-1)
        out[~ok] = np.nan
        return out, ok


@dataclass(frozen=True)
class TsaiRadial:
    """Tsai's one-term radial model, distorted -> undistorted: ``xu = xd (1 + kappa |xd|^2)``.

    ``kappa`` is in normalised units: a PETS file's ``kappa1`` (1/mm^2 on the sensor) times ``focal``^2.
    """

    kappa: float = 0.0

    @property
    def is_identity(self) -> bool:
        return self.kappa == 0.0

    def to_dict(self) -> dict:
        return {"model": "tsai", "kappa": self.kappa}

    @property
    def max_distorted_radius(self) -> float:
        """Radius where r (1 + kappa r^2) stops increasing; unbounded when kappa >= 0."""
        return float("inf") if self.kappa >= 0 else float(np.sqrt(-1.0 / (3.0 * self.kappa)))

    def undistort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        xy = np.asarray(xy, dtype=np.float64)
        r2 = np.sum(xy * xy, axis=-1)
        ok = np.isfinite(r2) & (np.sqrt(r2) <= self.max_distorted_radius)
        out = xy * (1.0 + self.kappa * r2)[..., None]
        out[~ok] = np.nan
        return out, ok

    def distort(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Solve rd (1 + kappa rd^2) = ru for rd by Newton's method, then scale the point by rd / ru."""
        xy = np.asarray(xy, dtype=np.float64)
        ru = np.sqrt(np.sum(xy * xy, axis=-1))
        finite = np.isfinite(ru)
        ru_safe = np.where(finite, ru, 0.0)
        rd = ru_safe.copy()
        converged = np.zeros(ru.shape, dtype=bool)
        r_cap = self.max_distorted_radius
        for _ in range(MAX_ITERATIONS):
            f = rd * (1.0 + self.kappa * rd * rd) - ru_safe
            converged = np.abs(f) <= TOLERANCE * (1.0 + ru_safe)
            if converged.all():
                break
            df = 1.0 + 3.0 * self.kappa * rd * rd
            safe = df > 1e-12
            rd = np.where(safe, rd - f / np.where(safe, df, 1.0), rd)
            rd = np.clip(rd, 0.0, r_cap)
        ok = finite & converged & (rd <= r_cap)
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(ru_safe > 0, rd / np.where(ru_safe > 0, ru_safe, 1.0), 1.0)
        out = xy * scale[..., None]
        out[~ok] = np.nan
        return out, ok


def distortion_from_dict(spec: dict) -> Distortion:
    """Build a model from its ``to_dict`` form (the scene YAML's ``distortion`` field)."""
    model = spec.get("model", "none")
    if model == "none":
        return NoDistortion()
    if model == "opencv":
        k = list(spec.get("k", []))
        if len(k) not in (4, 5):
            raise ValueError(f"opencv distortion needs 4 or 5 coefficients (k1, k2, p1, p2[, k3]), got {len(k)}")
        return BrownConrady(*map(float, k))
    if model == "tsai":
        return TsaiRadial(float(spec["kappa"]))
    raise ValueError(f"unknown distortion model {model!r} (expected none, opencv or tsai)")
