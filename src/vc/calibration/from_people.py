"""A camera solved from the people who walk through its view: their head and foot points alone (issue 60).

An installer has the video, not a tape measure. People are a calibration object the camera sees all day: each is a
vertical segment of about the same length standing on the ground. Their head-to-foot lines meet at the vertical
vanishing point, and the heads and feet of people of one stature seen at two depths meet on the horizon (Lv, Zhao &
Nevatia, "Camera calibration from video of a walking human", PAMI 2006; Krahnstoever & Mendonca, "Bayesian
autocalibration for surveillance", ICCV 2005). Together they fix the focal length, the tilt and the roll; the
height of the camera is known only in units of the people's stature, so a stature prior sets the scale
(:data:`STATURE_M`, stated in every result).

**The model.** A pinhole with square pixels, no skew, its principal point at the image centre, no distortion, on a
flat ground; the camera ``height_m`` above the ground, looking down by ``tilt_deg``, rolled by ``roll_deg``. The
world's x and y on the ground are the camera's own (its foot at the origin, looking along +y): a layout drawn in
pixels needs no more. For a person seen with feet at pixel ``f``, the model sends ``f`` to the ground, stands a
person of the prior's stature there and projects the head; the residual is the observed head's offset from that,
in units of the person's height in pixels (a 5 % stature error weighs the same near and far).

**The fit.** A coarse grid over focal length, tilt and height (roll 0) finds the basin; a bounded least squares with
a soft-L1 loss refines it; people whose residual is beyond :data:`OUTLIER_MADS` robust deviations (children,
cyclists, a person merged with a neighbour or a shadow) are dropped and the fit repeated. A focal length given by
the user is held fixed. The uncertainty of each parameter is its spread over fits to resamples of the tracks (a track
is one person: its sightings are not independent), the bootstrap Lv et al. and Tang et al. (ICPR 2016) report; and
the focal length's profile (:func:`focal_profile`) says whether the people determine it at all.

**Where it fails**, and says so through its uncertainty or by refusing: too few people (:data:`MIN_TRACKS`); people
all at one depth, or walking one way along one line (the horizon is then barely constrained); a camera looking
nearly straight down (head-foot lines all but parallel to the optical axis: tilt and focal trade off) or nearly
level (head-foot lines parallel in the image: the vertical vanishing point is at infinity and the focal length is
not observable; :data:`MAX_FOCAL_SPREAD`, :data:`MIN_PROFILE_RISE`). What it measures on real cameras is in
docs/own_camera.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from vc.calibration.camera import Camera, look_at
from vc.errors import InputError

#: The mean stature of the adults in view (m), which sets the scale: adults of Europe and North America average
#: 1.64-1.78 m by sex and country (NCD-RisC, "A century of trends in adult human height", eLife 2016); with shoes on,
#: and men and women together, 1.70 m. A camera's height is solved as a multiple of it.
STATURE_M = 1.70
#: Fewer people than this leave the horizon to chance: refused.
MIN_TRACKS = 8
#: Residuals (share of a person's pixel height) beyond this many median absolute deviations are outliers.
OUTLIER_MADS = 3.5
#: The soft-L1 loss's scale: a 4 % stature deviation, one standard deviation of adult stature.
LOSS_SCALE = 0.04
#: Resamples of the tracks for the uncertainty.
BOOTSTRAP = 100
#: A focal length whose bootstrap spread is more than this share of it is not observable from these people (a level
#: camera, or people at one depth): it must be given.
MAX_FOCAL_SPREAD = 0.25
#: The focal length is determined only where cameras with these multiples of it (the others fitted anew) explain
#: the people worse, their median residual higher by this share at least. A focal length off by a factor of two is
#: of no use; drawn walkers all at one depth, or seen from eye level or from straight above, rise by 0-5 % there,
#: walkers spread over depth by 30 % and more (experiments/2026-11-30-where-walker-calibration-fails).
PROFILE_FOCAL_FACTORS = (0.5, 2.0)
MIN_PROFILE_RISE = 0.05
#: The coarse grid: focal lengths as multiples of the image width, tilts (degrees), heights (m).
GRID_FOCAL_WIDTHS = np.geomspace(0.35, 4.0, 14)
GRID_TILT_DEG = np.linspace(1.0, 80.0, 17)
GRID_HEIGHT_M = np.geomspace(1.5, 40.0, 10)
PARAMETERS = ("focal_px", "tilt_deg", "roll_deg", "height_m")


@dataclass(frozen=True)
class PeopleCalibration:
    """A camera solved from people, with how sure it is."""

    camera: Camera
    focal_px: float
    tilt_deg: float
    roll_deg: float
    height_m: float
    focal_given: bool
    stature_m: float
    sightings: int  # head and foot pairs used
    tracks: int  # people they came from
    inliers: np.ndarray = field(repr=False)  # (N,) bool: the sightings the fit kept, in the order given
    residual: float  # median |residual| of the inliers, share of a person's pixel height
    spread: dict[str, float] = field(default_factory=dict)  # bootstrap standard deviation per parameter
    profile: tuple[float, ...] = ()  # focal_profile's ratios (none when the focal length is given)

    @property
    def focal_spread_share(self) -> float:
        """The focal length's bootstrap spread as a share of it (0 when given)."""
        return self.spread.get("focal_px", 0.0) / self.focal_px

    @property
    def focal_observable(self) -> bool:
        """Given, or solved with a spread within :data:`MAX_FOCAL_SPREAD`, and explained worse by half and by twice
        that focal length (:func:`focal_profile`, by at least :data:`MIN_PROFILE_RISE`)."""
        return self.focal_given or (self.focal_spread_share <= MAX_FOCAL_SPREAD
                                    and all(ratio >= 1.0 + MIN_PROFILE_RISE for ratio in self.profile))

    def to_dict(self) -> dict:
        return {"focal_px": round(self.focal_px, 2), "focal_given": self.focal_given,
                "tilt_deg": round(self.tilt_deg, 3), "roll_deg": round(self.roll_deg, 3),
                "height_m": round(self.height_m, 3), "stature_m": self.stature_m, "sightings": self.sightings,
                "tracks": self.tracks, "outliers": int((~self.inliers).sum()),
                "median_residual": round(self.residual, 4),
                "focal_profile": {f"x{factor:g}": round(ratio, 3) for factor, ratio
                                  in zip(PROFILE_FOCAL_FACTORS, self.profile, strict=False)},  # none when given
                "uncertainty": {name: round(value, 4) for name, value in self.spread.items()}}


def people_from_dict(data: dict, size: tuple[int, int]) -> PeopleCalibration:
    """A solution as :meth:`PeopleCalibration.to_dict` wrote it, for an image of ``size``: its camera, spread and
    profile (the sightings are not in it; ``inliers`` is empty). KeyError or ValueError on a malformed one."""
    focal, tilt, roll, height = (float(data[name]) for name in PARAMETERS)
    values = [focal, tilt, roll, height, float(data["stature_m"])]
    if not all(math.isfinite(value) for value in values) or focal <= 0 or height <= 0:
        raise ValueError("focal_px and height_m must be positive numbers")
    spread = {name: float(value) for name, value in data.get("uncertainty", {}).items() if name in PARAMETERS}
    return PeopleCalibration(camera_of(size, focal, tilt, roll, height), focal, tilt, roll, height,
                             bool(data["focal_given"]), values[4], int(data["sightings"]), int(data["tracks"]),
                             np.zeros(0, bool), float(data["median_residual"]), spread,
                             tuple(float(value) for value in data.get("focal_profile", {}).values()))


def camera_of(size: tuple[int, int], focal_px: float, tilt_deg: float, roll_deg: float, height_m: float) -> Camera:
    """The model's camera: at (0, 0, ``height_m``), looking along +y and down by ``tilt_deg``, rolled by
    ``roll_deg``, principal point at the image centre."""
    width, height = size
    tilt = math.radians(tilt_deg)
    eye = np.array([0.0, 0.0, height_m])
    R, t = look_at(eye, eye + np.array([0.0, math.cos(tilt), -math.sin(tilt)]), roll_deg)
    K = np.array([[focal_px, 0.0, (width - 1) / 2.0], [0.0, focal_px, (height - 1) / 2.0], [0.0, 0.0, 1.0]])
    return Camera(width, height, K, R, t)


def predicted_heads(camera: Camera, feet: np.ndarray, stature_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Where ``camera`` sees the head of a person of ``stature_m`` standing on each of ``feet`` (N, 2 px), and
    whether it can (the feet see the ground and the head is in front of the camera)."""
    hit = camera.ground_from_pixels(feet)
    projected = camera.project(np.c_[hit.points[:, :2], np.full(len(feet), stature_m)])
    return projected.uv, hit.ok & projected.ok


def _residuals(params: np.ndarray, size: tuple[int, int], heads: np.ndarray, feet: np.ndarray,
               stature_m: float) -> np.ndarray:
    """Per sighting, the observed head's offset (x, y) from the model's, over the person's pixel height."""
    focal, tilt, roll, height = params
    if focal <= 1.0 or height <= 0.05 or not 0.05 < tilt < 89.9:
        return np.full(2 * len(heads), 1e3)
    predicted, ok = predicted_heads(camera_of(size, focal, tilt, roll, height), feet, stature_m)
    scale = np.maximum(np.linalg.norm(heads - feet, axis=1), 1.0)[:, None]
    offset = (heads - predicted) / scale
    offset[~ok] = 1.0  # feet above the horizon under this model: as far off as a whole person
    return offset.ravel()


class _Parameters:
    """The parameters being solved: all four, or three with the focal length held at the user's value."""

    def __init__(self, size: tuple[int, int], focal_px: float | None) -> None:
        self.size, self.focal_px = size, focal_px

    def full(self, free: np.ndarray) -> np.ndarray:
        return np.asarray(free, np.float64) if self.focal_px is None else np.r_[self.focal_px, free]

    def free(self, full: np.ndarray) -> np.ndarray:
        return np.asarray(full, np.float64) if self.focal_px is None else np.asarray(full[1:], np.float64)

    def bounds(self) -> tuple[list[float], list[float]]:
        """What a surveillance camera can be: a focal length of 0.2 to 20 image widths (a fisheye's to a long
        telephoto's), looking down by 0.5 to 89 degrees, rolled by at most 30, 0.5 to 100 m above the ground."""
        low, high = [0.2 * self.size[0], 0.5, -30.0, 0.5], [20.0 * self.size[0], 89.0, 30.0, 100.0]
        return (low, high) if self.focal_px is None else (low[1:], high[1:])

    def x_scale(self) -> np.ndarray:
        return self.free(np.array([self.size[0], 10.0, 5.0, 5.0]))

    def residuals(self, free: np.ndarray, heads: np.ndarray, feet: np.ndarray, stature_m: float) -> np.ndarray:
        return _residuals(self.full(free), self.size, heads, feet, stature_m)


def _grid_start(parameters: _Parameters, heads: np.ndarray, feet: np.ndarray, stature_m: float) -> np.ndarray:
    """The coarse grid's best (focal, tilt, roll 0, height) by the median residual."""
    focals = GRID_FOCAL_WIDTHS * parameters.size[0] if parameters.focal_px is None else [parameters.focal_px]
    best, start = np.inf, None
    for focal in focals:
        for tilt in GRID_TILT_DEG:
            for height in GRID_HEIGHT_M:
                params = np.array([focal, tilt, 0.0, height])
                cost = float(np.median(np.abs(_residuals(params, parameters.size, heads, feet, stature_m))))
                if cost < best:
                    best, start = cost, params
    return start


def _inliers(params: np.ndarray, size: tuple[int, int], heads: np.ndarray, feet: np.ndarray,
             stature_m: float) -> np.ndarray:
    """The sightings within :data:`OUTLIER_MADS` robust deviations of the median residual under ``params``."""
    residual = np.linalg.norm(_residuals(params, size, heads, feet, stature_m).reshape(-1, 2), axis=1)
    median = float(np.median(residual))
    mad = float(np.median(np.abs(residual - median))) * 1.4826
    return residual <= median + OUTLIER_MADS * max(mad, 1e-3)


def _fit(parameters: _Parameters, heads: np.ndarray, feet: np.ndarray, stature_m: float,
         start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Robust refinement from ``start`` (all four parameters) on the sightings it does not already reject, then
    again on the refined fit's inliers; the parameters and the inlier mask."""
    params = start
    for _ in range(2):
        inliers = _inliers(params, parameters.size, heads, feet, stature_m)
        result = least_squares(parameters.residuals, parameters.free(params),
                               args=(heads[inliers], feet[inliers], stature_m), loss="soft_l1", f_scale=LOSS_SCALE,
                               x_scale=parameters.x_scale(), bounds=parameters.bounds(), method="trf")
        params = parameters.full(result.x)
    return params, _inliers(params, parameters.size, heads, feet, stature_m)


def _median_residual(params: np.ndarray, size: tuple[int, int], heads: np.ndarray, feet: np.ndarray,
                     stature_m: float) -> float:
    return float(np.median(np.linalg.norm(_residuals(params, size, heads, feet, stature_m).reshape(-1, 2), axis=1)))


def focal_profile(size: tuple[int, int], heads: np.ndarray, feet: np.ndarray, stature_m: float, params: np.ndarray,
                  inliers: np.ndarray) -> tuple[float, ...]:
    """How much worse the best camera with each of :data:`PROFILE_FOCAL_FACTORS` times the solved focal length
    explains the kept sightings: its median residual over the solution's. The bootstrap cannot show a focal length
    the people leave free: each resample starts at the solution and stays there (all people at one depth, or a
    camera at eye level, explain as well at any focal length)."""
    best = _median_residual(params, size, heads[inliers], feet[inliers], stature_m)
    ratios = []
    for factor in PROFILE_FOCAL_FACTORS:
        held = _Parameters(size, float(params[0]) * factor)
        other, _ = _fit(held, heads, feet, stature_m, _grid_start(held, heads, feet, stature_m))
        ratios.append(_median_residual(other, size, heads[inliers], feet[inliers], stature_m) / max(best, 1e-9))
    return tuple(ratios)


def solve(heads: np.ndarray, feet: np.ndarray, tracks: np.ndarray, size: tuple[int, int],
          focal_px: float | None = None, stature_m: float = STATURE_M, bootstrap: int = BOOTSTRAP,
          seed: int = 0) -> PeopleCalibration:
    """The camera from people's (N, 2) ``heads`` and ``feet`` pixels, each sighting's track (person) in
    ``tracks``, in an image of ``size``, with the focal length fixed at ``focal_px`` when given; InputError when
    there are too few people to solve it. Deterministic for a ``seed`` (the bootstrap's resamples)."""
    heads, feet = np.asarray(heads, np.float64).reshape(-1, 2), np.asarray(feet, np.float64).reshape(-1, 2)
    tracks = np.asarray(tracks).reshape(-1)
    people = np.unique(tracks)
    if len(people) < MIN_TRACKS:
        raise InputError(None, "people", f"{len(people)} people were seen walking alone; the camera needs "
                                         f"{MIN_TRACKS} or more (a longer video, or --points)")
    if focal_px is not None and not (math.isfinite(focal_px) and focal_px > 0):
        raise InputError(None, "--focal", f"must be a positive number of pixels, got {focal_px}")
    parameters = _Parameters(size, focal_px)
    params, inliers = _fit(parameters, heads, feet, stature_m, _grid_start(parameters, heads, feet, stature_m))
    rng = np.random.default_rng(seed)
    draws = []
    for _ in range(bootstrap):
        chosen = rng.choice(people, len(people), replace=True)
        rows = np.concatenate([np.flatnonzero(tracks == person) for person in chosen])
        draws.append(_fit(parameters, heads[rows], feet[rows], stature_m, params)[0])
    spread = dict(zip(PARAMETERS, np.std(np.array(draws), axis=0).tolist(), strict=True)) if draws else {}
    profile = () if focal_px is not None else focal_profile(size, heads, feet, stature_m, params, inliers)
    residual = np.linalg.norm(_residuals(params, size, heads[inliers], feet[inliers], stature_m).reshape(-1, 2),
                              axis=1)
    focal, tilt, roll, height = (float(value) for value in params)
    return PeopleCalibration(camera_of(size, focal, tilt, roll, height), focal, tilt, roll, height,
                             focal_px is not None, stature_m, int(inliers.sum()),
                             int(len(np.unique(tracks[inliers]))), inliers, float(np.median(residual)), spread,
                             profile)


def pose_of(camera: Camera) -> dict[str, float]:
    """Any camera's focal length (mean of fx, fy), tilt below the horizontal, roll and height above the ground, as
    :func:`solve` reports them, for comparison."""
    axis = camera.R[2]
    tilt = math.degrees(math.asin(float(np.clip(-axis[2], -1.0, 1.0))))
    roll = math.degrees(math.atan2(float(camera.R[0][2]), float(-camera.R[1][2])))
    return {"focal_px": (camera.fx + camera.fy) / 2.0, "tilt_deg": tilt, "roll_deg": roll,
            "height_m": float(camera.center[2])}
