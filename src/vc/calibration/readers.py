"""Readers for the calibration files surveillance datasets ship, all returning one :class:`Camera`.

| format         | file                                   | world units in the file |
|----------------|----------------------------------------|-------------------------|
| ``tsai-xml``   | PETS 2009 ``View_00N.xml`` (Tsai 1987) | millimetres             |
| ``towncentre-ci`` | Oxford Town Centre ``.ci`` key/value | metres                  |
| ``opencv``     | ``cv::FileStorage`` YAML / JSON        | metres (``units`` to override) |
| ``ground-points`` | CSV of ``u, v, x, y``: image points and their measured ground positions (solved) | metres |
| ``homography`` | a 3x3 image -> ground homography, ETH/UCY ``H.txt`` (solved)  | metres |
| ``people``     | ``walkers.json``: ``vc-scene init``'s camera solved from walking people | metres (stature prior) |

``ground-points`` and ``homography`` are solved, not read (:mod:`vc.calibration.ground_points`): they need the image
size, and take the focal length in pixels when it is known (``focal_px``; otherwise it is solved with the principal
point at the image centre). A ``people`` camera may be refined by measured points named in the scene
(``calibration.points``; :mod:`vc.calibration.points_and_people`), which the scene loader applies.

Every reader raises :class:`vc.errors.InputError` naming the file and the field on a bad file. Readers return
cameras in metres; ``units`` converts files written in other units.
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path

import numpy as np

from vc.calibration.camera import Camera, rotation_from_quaternion, rotation_xyz
from vc.calibration.distortion import BrownConrady, TsaiRadial
from vc.calibration.from_people import PeopleCalibration, people_from_dict
from vc.calibration.ground_points import (
    calibrate_from_ground_points,
    camera_from_homography,
    read_ground_points,
    read_homography,
)
from vc.errors import InputError

#: Metres per file unit.
UNIT_SCALE = {"m": 1.0, "cm": 0.01, "mm": 0.001}


def _require_file(path: Path) -> None:
    if not path.is_file():
        raise InputError(path, "", "calibration file not found")


def _float(path: Path, where: str, value: str | None) -> float:
    if value is None:
        raise InputError(path, where, "missing")
    try:
        number = float(value)
    except ValueError:
        raise InputError(path, where, f"not a number: {value!r}") from None
    if not np.isfinite(number):
        raise InputError(path, where, f"not finite: {value!r}")
    return number


def _camera(path: Path, **kwargs) -> Camera:
    try:
        return Camera(**kwargs)
    except ValueError as error:
        raise InputError(path, "", f"inconsistent calibration: {error}") from None


def read_tsai_xml(path: Path, units: str = "mm") -> Camera:
    """PETS Tsai XML: ``<Geometry>``, ``<Intrinsic>``, ``<Extrinsic>`` elements with attributes.

    Tsai's sensor model maps to a pinhole ``K`` with ``fx = sx f / dpx``, ``fy = f / dpy`` and a radial model
    on normalised coordinates with ``kappa = kappa1 f^2`` (kappa1 is per mm^2 on the sensor).
    """
    path = Path(path)
    _require_file(path)
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as error:
        raise InputError(path, "", f"not valid XML: {error}") from None
    elements = {}
    for name in ("Geometry", "Intrinsic", "Extrinsic"):
        element = root.find(name)
        if element is None:
            raise InputError(path, name, "element missing (expected a PETS Tsai calibration)")
        elements[name] = element

    def get(element: str, attribute: str) -> float:
        return _float(path, f"{element}.{attribute}", elements[element].get(attribute))

    width, height = int(get("Geometry", "width")), int(get("Geometry", "height"))
    dpx, dpy = get("Geometry", "dpx"), get("Geometry", "dpy")
    focal, kappa1 = get("Intrinsic", "focal"), get("Intrinsic", "kappa1")
    cx, cy, sx = get("Intrinsic", "cx"), get("Intrinsic", "cy"), get("Intrinsic", "sx")
    for field, value in (("Geometry.dpx", dpx), ("Geometry.dpy", dpy), ("Intrinsic.focal", focal),
                         ("Intrinsic.sx", sx)):
        if value <= 0:
            raise InputError(path, field, f"must be positive, got {value}")
    K = np.array([[sx * focal / dpx, 0.0, cx], [0.0, focal / dpy, cy], [0.0, 0.0, 1.0]])
    R = rotation_xyz(get("Extrinsic", "rx"), get("Extrinsic", "ry"), get("Extrinsic", "rz"))
    t = np.array([get("Extrinsic", "tx"), get("Extrinsic", "ty"), get("Extrinsic", "tz")]) * _scale(path, units)
    return _camera(path, width=width, height=height, K=K, R=R, t=t, distortion=TsaiRadial(kappa1 * focal**2))


TOWNCENTRE_KEYS = (
    "FocalLengthX", "FocalLengthY", "PrincipalPointX", "PrincipalPointY",
    "TranslationX", "TranslationY", "TranslationZ",
    "RotationX", "RotationY", "RotationZ", "RotationW",
    "DistortionK1", "DistortionK2", "DistortionP1", "DistortionP2",
)


def read_towncentre_ci(path: Path, size: tuple[int, int] | None, units: str = "m") -> Camera:
    """Oxford Town Centre ``.ci``: ``Key: value`` lines; rotation is a world -> camera quaternion (x, y, z, w).

    The file does not state the image size, so the caller passes it (``size`` in the scene's ``calibration``).
    """
    path = Path(path)
    _require_file(path)
    if size is None:
        raise InputError(path, "size", "a .ci file does not state the image size: give calibration.size")
    values: dict[str, str] = {}
    for line in path.read_text(errors="replace").splitlines():
        match = re.match(r"\s*([A-Za-z][A-Za-z0-9]*)\s*[:=]?\s*(\S+)\s*$", line)
        if match:
            values[match.group(1)] = match.group(2)
    v = {key: _float(path, key, values.get(key)) for key in TOWNCENTRE_KEYS}
    skew = _float(path, "Skew", values.get("Skew", "0"))
    K = np.array([[v["FocalLengthX"], skew, v["PrincipalPointX"]], [0.0, v["FocalLengthY"], v["PrincipalPointY"]],
                  [0.0, 0.0, 1.0]])
    try:
        R = rotation_from_quaternion(v["RotationX"], v["RotationY"], v["RotationZ"], v["RotationW"])
    except ValueError as error:
        raise InputError(path, "RotationX..W", str(error)) from None
    t = np.array([v["TranslationX"], v["TranslationY"], v["TranslationZ"]]) * _scale(path, units)
    distortion = BrownConrady(v["DistortionK1"], v["DistortionK2"], v["DistortionP1"], v["DistortionP2"])
    return _camera(path, width=int(size[0]), height=int(size[1]), K=K, R=R, t=t, distortion=distortion)


def read_opencv(path: Path, size: tuple[int, int] | None = None, units: str = "m") -> Camera:
    """``cv::FileStorage`` YAML or JSON, as written by OpenCV's calibration tools.

    Intrinsics: ``camera_matrix`` (or ``K``), ``distortion_coefficients`` (or ``dist_coeffs``, ``D``: 4 or 5
    values), ``image_width``/``image_height`` (or ``size``). Extrinsics: ``R`` / ``rotation_matrix`` (3x3) or
    ``rvec`` (Rodrigues), and ``t`` / ``T`` / ``tvec`` / ``translation_vector``, mapping world -> camera.
    """
    import cv2  # OpenCV is the reference parser for its own layout (YAML 1.0 header, !!opencv-matrix tags).

    path = Path(path)
    _require_file(path)
    try:
        storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    except (cv2.error, SystemError) as error:  # the binding wraps some parse errors as SystemError
        reason = str(error).strip().splitlines()[-1] if str(error).strip() else "unreadable"
        raise InputError(path, "", f"not a cv::FileStorage YAML/JSON file ({reason})") from None
    if not storage.isOpened():
        raise InputError(path, "", "not a cv::FileStorage YAML/JSON file")
    try:
        def node(*names: str):
            for name in names:
                found = storage.getNode(name)
                if not found.empty() and not found.isNone():
                    return name, found
            return names[0], None

        def matrix(*names: str, shapes: tuple[tuple[int, ...], ...], required: bool = True) -> np.ndarray | None:
            name, found = node(*names)
            if found is None:
                if required:
                    raise InputError(path, names[0], "missing")
                return None
            value = found.mat() if found.isMap() else np.array([found.at(i).real() for i in range(found.size())])
            if value is None:
                raise InputError(path, name, "not a matrix")
            value = np.asarray(value, dtype=np.float64)
            for shape in shapes:
                if value.size == int(np.prod(shape)):
                    if not np.isfinite(value).all():
                        raise InputError(path, name, "contains NaN or inf")
                    return value.reshape(shape)
            raise InputError(path, name, f"expected shape {' or '.join(map(str, shapes))}, got {value.shape}")

        K = matrix("camera_matrix", "K", shapes=((3, 3),))
        dist = matrix("distortion_coefficients", "dist_coeffs", "D", shapes=((5,), (4,)), required=False)
        rotation = matrix("R", "rotation_matrix", shapes=((3, 3),), required=False)
        if rotation is None:
            rvec = matrix("rvec", "rotation_vector", shapes=((3,),), required=False)
            if rvec is None:
                raise InputError(path, "R", "missing (give R / rotation_matrix or rvec)")
            rotation = cv2.Rodrigues(rvec.reshape(3, 1))[0]
        t = matrix("t", "T", "tvec", "translation_vector", shapes=((3,),))
        width_name, width = node("image_width")
        height_name, height = node("image_height")
        if width is not None and height is not None:
            file_size = (int(width.real()), int(height.real()))
        else:
            size_name, size_node = node("size", "image_size")
            file_size = tuple(int(v) for v in matrix(size_name, shapes=((2,),)).ravel()) if size_node else None
    finally:
        storage.release()
    if file_size is None and size is None:
        raise InputError(path, "image_width", "missing (or give calibration.size in the scene)")
    if file_size is not None and size is not None and tuple(size) != tuple(file_size):
        raise InputError(path, "image_width", f"file says {file_size[0]}x{file_size[1]}, scene says "
                                              f"{size[0]}x{size[1]}")
    width_px, height_px = file_size or size
    distortion = BrownConrady(*dist.ravel()) if dist is not None else BrownConrady()
    return _camera(path, width=width_px, height=height_px, K=K, R=rotation, t=t * _scale(path, units),
                   distortion=distortion)


def _scale(path: Path, units: str) -> float:
    if units not in UNIT_SCALE:
        raise InputError(path, "units", f"unknown unit {units!r} (expected one of {', '.join(UNIT_SCALE)})")
    return UNIT_SCALE[units]


def _solved_from_points(path: Path, size: tuple[int, int] | None, units: str | None,
                        focal_px: float | None) -> Camera:
    image, ground = read_ground_points(path, _scale(path, units or "m"))
    return calibrate_from_ground_points(image, ground, _required_size(path, size), focal_px, path).camera


def _solved_from_homography(path: Path, size: tuple[int, int] | None, units: str | None,
                            focal_px: float | None) -> Camera:
    image_to_ground = read_homography(path)
    scale = _scale(path, units or "m")
    try:
        ground_to_image = np.linalg.inv(np.diag([scale, scale, 1.0]) @ image_to_ground)
    except np.linalg.LinAlgError:
        raise InputError(path, "", "the homography is singular: it does not map the image onto a plane") from None
    return camera_from_homography(ground_to_image, _required_size(path, size), focal_px, path)


def _required_size(path: Path, size: tuple[int, int] | None) -> tuple[int, int]:
    if size is None:
        raise InputError(path, "size", "a solved calibration needs the image size: give calibration.size")
    return size


def _read(reader: Callable[[Path, tuple[int, int] | None, str], Camera], default_units: str
          ) -> Callable[[Path, tuple[int, int] | None, str | None, float | None], Camera]:
    """A file reader as a :data:`READERS` entry: the file holds its own focal length."""
    def read(path: Path, size: tuple[int, int] | None, units: str | None, focal_px: float | None) -> Camera:
        if focal_px is not None:
            raise InputError(path, "focal_px", "only a solved calibration (ground-points, homography) takes "
                                               "focal_px: this file gives its own intrinsics")
        return reader(path, size, units or default_units)
    return read


def read_people_solution(path: Path) -> PeopleCalibration:
    """The camera solved from the people walking through a video, as ``vc-scene init`` writes it
    (``walkers.json``: ``size`` and ``people``, see :mod:`vc.calibration.from_people`)."""
    try:
        document = json.loads(Path(path).read_text())
        size = (int(document["size"][0]), int(document["size"][1]))
        return people_from_dict(document["people"], size)
    except OSError as error:
        raise InputError(path, "", f"cannot read: {error.strerror or error}") from None
    except (ValueError, KeyError, TypeError, IndexError) as error:
        raise InputError(path, "people", f"not a solution written by vc-scene init ({error})") from None


#: Calibration formats by name, as written in a scene's ``calibration.format``: (path, size, units, focal_px).
READERS: dict[str, Callable[[Path, tuple[int, int] | None, str | None, float | None], Camera]] = {
    "tsai-xml": _read(lambda path, size, units: read_tsai_xml(path, units), "mm"),
    "towncentre-ci": _read(read_towncentre_ci, "m"),
    "opencv": _read(read_opencv, "m"),
    "ground-points": _solved_from_points,
    "homography": _solved_from_homography,
    "people": _read(lambda path, size, units: read_people_solution(path).camera, "m"),
}


def read_calibration(path: Path, format: str, size: tuple[int, int] | None = None,
                     units: str | None = None, focal_px: float | None = None) -> Camera:
    """Read (or solve) ``path`` as calibration ``format``; see :data:`READERS` for the names."""
    if format not in READERS:
        raise InputError(path, "format", f"unknown calibration format {format!r} "
                                         f"(expected one of {', '.join(sorted(READERS))})")
    return READERS[format](Path(path), size, units, focal_px)
