"""Load a scene YAML into a :class:`Scene`: validated fields, resolved paths, a camera, and a content hash.

All the ways a scene file can be wrong end here as one :class:`vc.errors.InputError` naming the file and the
field — YAML syntax, schema violations, missing or unreadable files, an image whose size is not the
calibration's — so that commands can print one line and exit with status 2.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from pydantic import ValidationError

from vc.calibration.camera import Camera
from vc.calibration.distortion import distortion_from_dict
from vc.calibration.points_and_people import calibrate_from_points_and_people
from vc.calibration.readers import UNIT_SCALE, read_calibration, read_people_solution
from vc.calibration.response_fit import ResponseFit, resolve_response
from vc.errors import InputError
from vc.io import image_size
from vc.scenes.layout import Layout
from vc.scenes.pixel_layout import PixelLayout
from vc.scenes.schema import Lighting, Priors, RegionPlanSpec, SceneFile, SolarLighting, ZoneSpec


@dataclass(frozen=True)
class Scene:
    """A loaded, validated scene: what every stage after ``vc-scene check`` starts from."""

    name: str
    path: Path
    image_path: Path
    camera: Camera
    response: str
    layout: Layout
    priors: Priors
    lighting: Lighting | SolarLighting | str
    effects: list[str] | str
    regions: RegionPlanSpec
    content_hash: str
    video_path: Path | None = None  # frames of the same camera, when the scene gives them
    exposure_s: float | None = None  # the camera's exposure time, when the scene gives it
    drawn_layout: PixelLayout | None = None  # the layout as drawn in pixels, when the scene gives it so
    zones: tuple[ZoneSpec, ...] = ()  # named zones a service reports people entering and leaving

    def camera_response(self) -> ResponseFit:
        """The camera response every stage decodes and encodes with: the one the scene names, or (``auto``) the
        one fitted on its background image, with the evidence."""
        return resolve_response(self.response, self.image_path)

    @property
    def folder(self) -> Path:
        return self.path.parent


def _field(location: tuple) -> str:
    return ".".join(str(part) for part in location) or "(top level)"


def _pydantic_error(path: Path, error: ValidationError) -> InputError:
    """The first (most specific) validation error as one line; pydantic's tagged-union tags are dropped."""
    first = error.errors(include_url=False)[0]
    parts = first["loc"]
    location = tuple(part for index, part in enumerate(parts)
                     if part not in ("box", "cylinder", "auto", "explicit", "solar")
                     and not (index and parts[index - 1] == "layout" and part in ("ground", "image")))
    message = first["msg"].removeprefix("Value error, ")
    if first["type"] == "missing":
        message = "missing required field"
    elif first["type"] == "extra_forbidden":
        message = "unknown field (check the spelling)"
    return InputError(path, _field(location), message)


def read_scene_file(path: Path) -> SceneFile:
    """Parse and validate the YAML (no file other than the YAML is touched)."""
    if not path.is_file():
        raise InputError(path, "", "scene file not found")
    try:
        raw = yaml.safe_load(path.read_text())
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else ""
        raise InputError(path, where, f"not valid YAML ({getattr(error, 'problem', None) or error})") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "not a text file") from None
    if not isinstance(raw, dict):
        raise InputError(path, "", "a scene file must be a YAML mapping (name, image, camera, layout, ...)")
    try:
        return SceneFile.model_validate(raw)
    except ValidationError as error:
        raise _pydantic_error(path, error) from None


def _camera(path: Path, spec: SceneFile) -> tuple[Camera, str, list[Path]]:
    """The scene's camera, its response, and the extra files it was read from (for the content hash)."""
    if spec.camera is not None:
        inline = spec.camera
        try:
            camera = Camera(
                width=inline.size[0], height=inline.size[1], K=np.asarray(inline.K), R=inline.rotation(),
                t=np.asarray(inline.t), distortion=distortion_from_dict(inline.distortion.model_dump()),
            )
        except ValueError as error:
            raise InputError(path, "camera", str(error)) from None
        return camera, inline.response, []
    reference = spec.calibration
    calibration_path = (path.parent / reference.path).resolve()
    if not calibration_path.is_file():
        raise InputError(path, "calibration.path", f"file not found: {calibration_path}")
    size = tuple(reference.size) if reference.size else None
    camera = read_calibration(calibration_path, reference.format, size, reference.units, reference.focal_px)
    if reference.points:
        camera = _refined_by_points(path, calibration_path, reference)
    if size is not None and camera.size != size:
        raise InputError(path, "calibration.size", f"scene says {size[0]}x{size[1]} but {calibration_path.name} "
                                                   f"says {camera.width}x{camera.height}")
    return camera, reference.response, [calibration_path]


def _refined_by_points(path: Path, calibration_path: Path, reference) -> Camera:
    """The people's camera of ``calibration_path`` refined by the scene's measured ``calibration.points``."""
    points = np.asarray(reference.points, np.float64).reshape(-1, 4)
    people = read_people_solution(calibration_path)
    try:
        return calibrate_from_points_and_people(points[:, :2], points[:, 2:] * UNIT_SCALE[reference.units or "m"],
                                                people).camera
    except InputError as error:
        field = ".".join(part for part in ("calibration.points", error.field) if part)
        raise InputError(path, field, error.reason) from None


def _image_path(path: Path, spec: SceneFile) -> Path:
    return (path.parent / spec.image).resolve()


def _resolve_image(path: Path, spec: SceneFile) -> Path:
    candidate = _image_path(path, spec)
    if not candidate.is_file():
        raise InputError(path, "image", f"file not found: {candidate}")
    return candidate


def load_scene(path: str | Path, require_image: bool = True) -> Scene:
    """Load and validate a scene YAML; see the module docstring for what is checked.

    ``require_image=False`` is for making the background itself (``vc-scene synthesize``): the image may not
    exist yet, and the content hash then covers the YAML and calibration only.
    """
    path = Path(path).resolve()
    spec = read_scene_file(path)
    camera, response, extra_files = _camera(path, spec)
    if not require_image:
        return _scene(path, spec, _image_path(path, spec), camera, response, extra_files)
    image_path = _resolve_image(path, spec)
    try:
        width, height = image_size(image_path)
    except InputError as error:
        raise InputError(path, "image", f"{image_path.name}: {error.reason}") from None
    if (width, height) != camera.size:
        raise InputError(path, "image", f"{image_path.name} is {width}x{height} but the camera is "
                                        f"{camera.width}x{camera.height}")
    return _scene(path, spec, image_path, camera, response, [image_path, *extra_files])


def _video_path(path: Path, spec: SceneFile) -> Path | None:
    if spec.video is None:
        return None
    video = (path.parent / spec.video).resolve()
    if not video.exists():
        raise InputError(path, "video", f"not found: {video}")
    return video


def _video_files(video: Path | None) -> list[Path]:
    """The files a scene's video is (one file, or the images of a folder) for the content hash."""
    if video is None:
        return []
    return [video] if video.is_file() else sorted(p for p in video.iterdir() if p.is_file())


def top_level_span(text: str, key: str) -> tuple[int, int] | None:
    """Where the top-level entry ``key`` of a YAML mapping's ``text`` lies: from the start of its key's line to the
    end of its value's (a flow value ends mid-line: to the end of that line); None when absent. The text around it
    keeps its comments and layout, which a parse and dump would lose."""
    root = yaml.compose(text)
    for node_key, value in root.value if isinstance(root, yaml.MappingNode) else ():
        if node_key.value == key:
            start = text.rfind("\n", 0, node_key.start_mark.index) + 1
            end = value.end_mark.index
            if end < len(text) and text[end - 1] != "\n":
                newline = text.find("\n", end)
                end = len(text) if newline < 0 else newline + 1
            return start, end
    return None


def _hashed_yaml(path: Path) -> bytes:
    """The scene file as its content hash covers it: as written, less its ``zones`` entry (cut from the text, so that
    adding zones to a scene leaves its hash as it was). Zones change nothing rendered or trained: adding one needs
    only ``vc-export --scene``, not a new compile."""
    raw = path.read_bytes()
    text = raw.decode()
    span = top_level_span(text, "zones")
    return raw if span is None else (text[:span[0]] + text[span[1]:]).encode()


def _scene(path: Path, spec: SceneFile, image_path: Path, camera: Camera, response: str,
           hashed_files: list[Path]) -> Scene:
    video = _video_path(path, spec)
    digest = hashlib.sha256(_hashed_yaml(path))
    for file in (*hashed_files, *_video_files(video)):
        digest.update(file.read_bytes())
    drawn = spec.layout if isinstance(spec.layout, PixelLayout) else None
    layout = drawn.to_ground(camera, path) if drawn is not None else spec.layout
    return Scene(
        name=spec.name, path=path, image_path=image_path, camera=camera, response=response, layout=layout,
        priors=spec.priors, lighting=spec.lighting, effects=spec.effects, regions=spec.regions,
        content_hash=digest.hexdigest(), video_path=video,
        exposure_s=(spec.camera or spec.calibration).exposure_s, drawn_layout=drawn,
        zones=tuple(spec.zones),
    )
