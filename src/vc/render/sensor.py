"""Mitsuba sensors that see exactly what a calibrated :class:`Camera` sees.

Mitsuba's ``perspective`` sensor is an ideal pinhole: one focal length, no skew, no distortion. A real camera is
rendered in two steps that keep the geometry exact:

1. :func:`ideal_view` picks an ideal pinhole camera with the same pose whose image contains the real camera's
   whole field of view (plus a margin for interpolation), and :func:`perspective_sensor` turns it into a
   Mitsuba sensor;
2. :meth:`IdealView.warp` resamples the ideal render into the real image: each real pixel is undistorted to
   normalised coordinates, which the ideal camera maps to a pixel of its image.

Pixel convention: OpenCV's, the centre of the top-left pixel is (0, 0). Mitsuba's film puts that centre at
(0.5, 0.5); the shift lives in :func:`film_position` and nowhere else. Axis convention: Mitsuba's camera looks
along its local +z with +x pointing to the image's *left* and +y *up* (verified by ``test_render_sensor``),
so OpenCV's camera axes (x right, y down) enter ``to_world`` negated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from vc.calibration.camera import Camera
from vc.render.mitsuba_setup import mitsuba

#: Ideal-image pixels kept around the real field of view: bilinear sampling reads one pixel beyond a point.
WARP_MARGIN_PX = 2.0
#: An ideal image larger than this (per side) means a field of view a pinhole cannot reasonably cover.
MAX_IDEAL_SIDE_PX = 16384
#: Where the warp looks for real pixels that cannot be undistorted: far enough outside to sample black.
OUTSIDE_PX = -16.0
#: Relative tolerance under which two focal lengths count as equal (the camera is already ideal).
FOCAL_RTOL = 1e-9


def film_position(uv: np.ndarray) -> np.ndarray:
    """OpenCV pixel coordinates -> Mitsuba film coordinates (pixels, top-left pixel centre at (0.5, 0.5)).

    The one place the half-pixel shift between the two conventions lives.
    """
    return np.asarray(uv, dtype=np.float64) + 0.5


def is_ideal(camera: Camera) -> bool:
    """Whether Mitsuba's pinhole reproduces ``camera`` as is: square pixels, no skew, no distortion."""
    return (
        math.isclose(camera.fx, camera.fy, rel_tol=FOCAL_RTOL)
        and camera.K[0, 1] == 0.0
        and camera.distortion.is_identity
    )


def camera_to_world(camera: Camera) -> np.ndarray:
    """Mitsuba's ``to_world`` (4x4) for the pose of ``camera``: columns -x, -y, z of OpenCV's axes, centre."""
    matrix = np.eye(4)
    matrix[:3, 0] = -camera.R[0]
    matrix[:3, 1] = -camera.R[1]
    matrix[:3, 2] = camera.R[2]
    matrix[:3, 3] = camera.center
    return matrix


def perspective_sensor(camera: Camera, spp: int, rfilter: str = "box", sampler: str = "independent") -> dict:
    """A Mitsuba ``perspective`` sensor dict (with ``hdrfilm`` and sampler) imaging exactly like ``camera``.

    ``camera`` must be ideal (:func:`is_ideal`); use :func:`ideal_view` for any other. The default ``box``
    reconstruction filter integrates each pixel's own area, as a sensor does, and never blurs neighbours
    together (which matters for masks and for the centroid test of the pixel convention).
    """
    if not is_ideal(camera):
        raise ValueError("perspective_sensor needs an ideal pinhole camera (fx == fy, no skew, no distortion); "
                         "render ideal_view(camera).ideal and warp instead")
    if spp < 1:
        raise ValueError(f"samples per pixel must be at least 1, got {spp}")
    mi = mitsuba()
    # The principal point's offset from the film centre, as a fraction of the film size; Mitsuba adds it to
    # the sample position, so a positive offset moves the principal point towards the top-left.
    principal = film_position(np.array([camera.cx, camera.cy])) / np.array([camera.width, camera.height])
    offset_x, offset_y = 0.5 - principal
    return {
        "type": "perspective",
        "fov": math.degrees(2.0 * math.atan(camera.width / (2.0 * camera.fx))),
        "fov_axis": "x",
        "principal_point_offset_x": float(offset_x),
        "principal_point_offset_y": float(offset_y),
        "to_world": mi.ScalarTransform4f(camera_to_world(camera).tolist()),
        "film": {
            "type": "hdrfilm",
            "width": camera.width,
            "height": camera.height,
            "pixel_format": "rgb",
            "component_format": "float32",
            "rfilter": {"type": rfilter},
        },
        "sampler": {"type": sampler, "sample_count": int(spp)},
    }


@dataclass(frozen=True, eq=False)
class IdealView:
    """An ideal pinhole ``ideal`` that sees all of ``camera``'s view, and the maps from its image to ``camera``'s.

    ``map_x``/``map_y`` (float32, the real image's shape) give, for every real pixel, the ideal image's pixel
    that looks along the same ray; pixels outside the distortion model's domain map outside the ideal image
    and come out black. Both are None when ``camera`` is already ideal (then ``ideal`` is ``camera`` and
    :meth:`warp` returns its input as is).
    """

    camera: Camera
    ideal: Camera
    map_x: np.ndarray | None
    map_y: np.ndarray | None

    def warp(self, image: np.ndarray, interpolation: int = cv2.INTER_LINEAR) -> np.ndarray:
        """Resample an image rendered through ``ideal`` (H, W[, C]) into ``camera``'s image.

        OpenCV interpolates at 1/32 px steps, so positions are exact to within 1/64 px.
        """
        if image.shape[:2] != (self.ideal.height, self.ideal.width):
            raise ValueError(f"image is {image.shape[1]}x{image.shape[0]} but the ideal camera is "
                             f"{self.ideal.width}x{self.ideal.height}")
        if self.map_x is None or self.map_y is None:
            return image
        return remap(image, self.map_x, self.map_y, interpolation)

    def warp_window(self, window: np.ndarray, x0: int, y0: int, interpolation: int = cv2.INTER_LINEAR,
                    outside: float = 0.0) -> tuple[tuple[slice, slice], np.ndarray]:
        """Warp only a window of the ideal image (its top-left pixel at ``(x0, y0)``): the real pixels that read
        from it, as (the slices of the real image they fill, their values). Real pixels in those slices whose
        ray falls outside the window get ``outside``. For a camera that is already ideal this is a paste.
        """
        height, width = window.shape[:2]
        if self.map_x is None or self.map_y is None:
            return (slice(y0, y0 + height), slice(x0, x0 + width)), window
        reads_window = ((self.map_x > x0 - 1) & (self.map_x < x0 + width) & (self.map_y > y0 - 1)
                        & (self.map_y < y0 + height))
        rows, columns = np.nonzero(reads_window.any(axis=1))[0], np.nonzero(reads_window.any(axis=0))[0]
        if len(rows) == 0:
            return (slice(0, 0), slice(0, 0)), window[:0, :0]
        area = (slice(rows[0], rows[-1] + 1), slice(columns[0], columns[-1] + 1))
        return area, remap(window, self.map_x[area] - np.float32(x0), self.map_y[area] - np.float32(y0),
                           interpolation, outside)


def remap(image: np.ndarray, map_x: np.ndarray, map_y: np.ndarray, interpolation: int = cv2.INTER_LINEAR,
          outside: float = 0.0) -> np.ndarray:
    """``cv2.remap`` for any number of channels (OpenCV takes at most 4), ``outside`` beyond the source."""
    if image.ndim == 3 and image.shape[2] > 4:
        groups = [remap(image[..., i:i + 4], map_x, map_y, interpolation, outside)
                  for i in range(0, image.shape[2], 4)]
        return np.concatenate(groups, axis=2)
    if image.ndim == 3 and image.shape[2] == 0:
        return np.zeros((*map_x.shape, 0), image.dtype)
    warped = cv2.remap(image, map_x, map_y, interpolation, borderMode=cv2.BORDER_CONSTANT,
                       borderValue=(outside,) * 4)
    return warped.reshape(*map_x.shape, *image.shape[2:])


def _pixel_grid(camera: Camera) -> np.ndarray:
    """Centres of all pixels of ``camera``, (H, W, 2)."""
    u, v = np.meshgrid(np.arange(camera.width, dtype=np.float64), np.arange(camera.height, dtype=np.float64))
    return np.stack([u, v], axis=-1)


def ideal_view(camera: Camera, margin_px: float = WARP_MARGIN_PX) -> IdealView:
    """The ideal pinhole camera that covers ``camera``'s field of view, and the warp between the two images.

    Its focal length is the larger of fx and fy, so the ideal image is nowhere coarser than the real one at the
    image centre; its size and principal point come from the undistorted normalised coordinates of every real
    pixel centre, extended by ``margin_px`` on each side.
    """
    if is_ideal(camera):
        return IdealView(camera, camera, None, None)
    normalised, ok = camera.distortion.undistort(camera.normalised_from_pixels(_pixel_grid(camera)))
    if not ok.any():
        raise ValueError("no pixel of the camera can be undistorted: the distortion model is unusable")
    focal = max(camera.fx, camera.fy)
    low = normalised[ok].min(axis=0) * focal - margin_px
    high = normalised[ok].max(axis=0) * focal + margin_px
    width, height = (int(math.ceil(n)) + 1 for n in high - low)
    if max(width, height) > MAX_IDEAL_SIDE_PX:
        raise ValueError(f"the camera's field of view needs a {width}x{height} pinhole image; the lens is too "
                         "wide to render through a pinhole")
    K = np.array([[focal, 0.0, -low[0]], [0.0, focal, -low[1]], [0.0, 0.0, 1.0]])
    ideal = Camera(width=width, height=height, K=K, R=camera.R, t=camera.t)
    ideal_pixels = ideal.pixels_from_normalised(normalised)
    ideal_pixels[~ok] = OUTSIDE_PX
    map_x, map_y = (np.ascontiguousarray(ideal_pixels[..., i], dtype=np.float32) for i in range(2))
    return IdealView(camera, ideal, map_x, map_y)
