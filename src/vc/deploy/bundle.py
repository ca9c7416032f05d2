"""The bundle an appliance embeds: ``manifest.json`` + ``models/<region>.onnx`` + ``models/<region>.heights.npy`` +
``decoder.txt`` (+ ``reference/background.npz``, the scene's background as scene fitness measures frames against it),
as a folder or a zip of one (numpy and the standard library only).

Nothing is loaded before the whole bundle checks out: with a public key, the manifest's signature
(:mod:`vc.deploy.signing`); the format and its version, every field the runtime reads, every listed file present,
inside the bundle and matching its SHA-256. A bad bundle is refused with one :class:`~vc.errors.InputError`
naming the file and the field.

Each region's ``decode`` names the decoding it was exported with. A switch the decoder has settled
(:data:`~vc.deploy.decode.SETTLED_SWITCHES`) is read past at its settled value, the decoding every bundle gets, and
refused at the other, as is a bundle of the retired 19-map layout (``output.channels``): the refusal names the
field. The format itself is unchanged, and so is its version (docs/decisions/0003-decoder-settings.md).

The manifest's ``reference`` (``background``, ``background_sha256``) is optional: a bundle exported without its
scene, or before scene fitness, loads as before, without a reference, and its frames' fitness is ``unknown``
(:mod:`vc.deploy.fitness`). One that names a reference is checked like every member, and its content too: a
reference that does not fit the bundle's frames is refused by name. Its optional ``fit_range`` is how far frames may
depart from the background and still be fit, what the networks were compiled to see
(:class:`~vc.deploy.fitness.FitRange`; absent: the background's one look).

The manifest's optional ``decoder_file`` names the flat file a decoder outside Python reads
(:mod:`vc.deploy.decoder_file`), checked like every member.

The manifest's optional ``facing`` (``model``, ``model_sha256``, ``crop_size``; ``across_output`` where the model
also reads where faces point) names the facing model, which reads from each person's crop whether they are seen
from the front or from behind, and where their face points (:mod:`vc.deploy.facing`); a bundle without it orders a
person's left and right by its networks' handedness maps, as before.

The manifest's optional ``crop_pose`` (``model``, ``model_sha256``, ``crop_size``, ``map_stride``) names the keypoint
model, which reads each person's keypoints again from their own crop (:mod:`vc.deploy.crop_pose`); a bundle without
it reports the keypoints its networks place, as before.

The manifest's optional ``zones`` are the scene's named areas, in frame pixels or on the ground, that a service
reports people entering and leaving (:mod:`vc.deploy.zones`); a malformed zone is refused by name.
"""

from __future__ import annotations

import hashlib
import io
import json
import zipfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath, PureWindowsPath

import numpy as np

from vc.deploy.decode import DecodeConfig, RetiredSetting, stored_decode_fields
from vc.deploy.fitness import BACKGROUND_ONLY, FitRange, SceneReference
from vc.deploy.heatmaps import ANATOMICAL_CHANNELS, LAYOUTS
from vc.deploy.signing import SIGNATURE, verify_manifest
from vc.deploy.zones import Zone, zones_from_manifest
from vc.errors import InputError

BUNDLE_FORMAT = "visual-compiler bundle"
BUNDLE_FORMAT_VERSION = 1
MANIFEST = "manifest.json"
MODELS = "models"
#: The manifest's optional entry for the scene fitness reference, and the member it names in bundles vc-export writes.
REFERENCE, REFERENCE_MEMBER = "reference", "reference/background.npz"
#: The manifest's optional entry for the facing model, and the member it names in bundles vc-export writes.
FACING, FACING_MEMBER = "facing", "models/facing.onnx"
#: The manifest's optional entry for the keypoint model, and the member it names in bundles vc-export writes.
CROP_POSE, CROP_POSE_MEMBER = "crop_pose", "models/crop_pose.onnx"
#: Why a bundle without a reference reports its frames' fitness as unknown.
NO_REFERENCE = ("the bundle carries no background reference (exported without its scene, or before scene fitness: "
                "export the run again with vc-export --scene)")


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


@dataclass(frozen=True)
class RegionEntry:
    """One region of a bundle, as the runtime uses it."""

    name: str
    crop_window: tuple[int, int, int, int]  # x0, y0, width, height in frame pixels
    input_size: tuple[int, int]  # network input width, height
    decode: DecodeConfig
    owned_image_area: dict  # GeoJSON (Multi)Polygon in frame pixels: detections whose foot falls here are kept
    model: bytes  # the ONNX model
    expected_height_px: np.ndarray  # (h, w) per heat-map cell
    precision: str  # fp32, fp16 or int8


@dataclass(frozen=True)
class Bundle:
    path: Path
    manifest: dict
    regions: list[RegionEntry]
    reference: SceneReference | None = None  # the scene's background for scene fitness; None: not carried
    fit_range: FitRange = BACKGROUND_ONLY  # how far a fit frame may depart from it (the module docstring)
    zones: tuple[Zone, ...] = ()  # the scene's named zones (vc.deploy.zones)
    facing: bytes | None = None  # the facing model (ONNX, vc.deploy.facing); None: not carried
    crop_pose: bytes | None = None  # the keypoint model (ONNX, vc.deploy.crop_pose); None: not carried

    @property
    def frame_size(self) -> tuple[int, int]:
        width, height = self.manifest["frame_size"]
        return int(width), int(height)


class _Files:
    """Read access to a bundle folder or zip by relative name."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.archive: zipfile.ZipFile | None = None
        if path.is_file():
            try:
                self.archive = zipfile.ZipFile(path)
                broken = self.archive.testzip()
            except (zipfile.BadZipFile, OSError) as error:
                raise InputError(path, "", f"not a readable zip bundle ({error})") from None
            if broken is not None:
                raise InputError(path, broken, "corrupted member (CRC mismatch)")
        elif not path.is_dir():
            raise InputError(path, "", "bundle not found (expected a folder or a .zip)")

    def _check_member(self, name: str, field: str) -> None:
        """A member is named by a relative path inside the bundle: an absolute path, a ``..`` step or (in a folder)
        a symbolic link leading out would let a rewritten manifest run a model from anywhere on the appliance."""
        parts = PurePosixPath(name.replace("\\", "/")).parts
        if not name or PurePosixPath(name).is_absolute() or PureWindowsPath(name).drive or ".." in parts:
            raise InputError(self.path, field, f"{name!r} is not a path inside the bundle (absolute, or with '..')")
        if self.archive is None:
            root = self.path.resolve()
            if not (self.path / name).resolve().is_relative_to(root):
                raise InputError(self.path, field, f"{name} leads outside the bundle (a symbolic link)")

    def has(self, name: str) -> bool:
        if self.archive is not None:
            return name in self.archive.namelist()
        return (self.path / name).is_file()

    def read(self, name: str, field: str) -> bytes:
        self._check_member(name, field)
        try:
            if self.archive is not None:
                return self.archive.read(name)
            return (self.path / name).read_bytes()
        except (KeyError, FileNotFoundError, IsADirectoryError):
            raise InputError(self.path, field, f"{name} is missing from the bundle") from None
        except (OSError, zipfile.BadZipFile) as error:
            raise InputError(self.path, field, f"cannot read {name} ({error})") from None


def _require(mapping: dict, key: str, kind: type | tuple[type, ...], where: str, path: Path) -> object:
    if not isinstance(mapping, dict) or key not in mapping:
        raise InputError(path, f"{where}{key}", "missing")
    value = mapping[key]
    if not isinstance(value, kind):
        raise InputError(path, f"{where}{key}", f"expected {getattr(kind, '__name__', kind)}, got "
                                                f"{type(value).__name__}")
    return value


def _checked(files: _Files, entry: dict, key: str, where: str) -> bytes:
    name = _require(entry, key, str, where, files.path)
    data = files.read(name, f"{where}{key}")
    expected = _require(entry, f"{key}_sha256", str, where, files.path)
    if sha256(data) != expected:
        raise InputError(files.path, f"{where}{key}_sha256", f"{name} does not match its SHA-256 (tampered or "
                                                              "damaged)")
    return data


def load_bundle(path: str | Path, public_key: Path | bytes | None = None) -> Bundle:
    """Validate and read a bundle folder or zip (see the module docstring); with ``public_key`` (a PEM file or its
    bytes), only a bundle whose manifest that key's owner signed."""
    path = Path(path)
    files = _Files(path)
    manifest_bytes = files.read(MANIFEST, "")
    if public_key is not None:
        signature = files.read(SIGNATURE, SIGNATURE) if files.has(SIGNATURE) else None
        verify_manifest(manifest_bytes, signature, public_key, path)
    try:
        manifest = json.loads(manifest_bytes)
    except json.JSONDecodeError as error:
        raise InputError(path, MANIFEST, f"not valid JSON ({error})") from None
    if not isinstance(manifest, dict) or manifest.get("format") != BUNDLE_FORMAT:
        raise InputError(path, f"{MANIFEST}: format", f"not a {BUNDLE_FORMAT}")
    version = manifest.get("format_version")
    if version != BUNDLE_FORMAT_VERSION:
        raise InputError(path, f"{MANIFEST}: format_version", f"unsupported bundle format {version!r} (this runtime "
                                                              f"reads {BUNDLE_FORMAT_VERSION})")
    _require(manifest, "frame_size", list, f"{MANIFEST}: ", path)
    output = manifest.get("output")
    channels = output.get("channels") if isinstance(output, dict) else None
    if isinstance(channels, list) and len(channels) not in LAYOUTS:
        reason = (f"{len(channels)} heat maps, the layout of networks from before the handedness maps, which this "
                  f"runtime does not decode (docs/decisions/0003-decoder-settings.md); compile the scene again with "
                  f"this version" if len(channels) == ANATOMICAL_CHANNELS else
                  f"{len(channels)} heat maps; this runtime decodes the layouts of {', '.join(map(str, LAYOUTS))}")
        raise InputError(path, f"{MANIFEST}: output.channels", reason)
    regions = []
    for index, entry in enumerate(_require(manifest, "regions", list, f"{MANIFEST}: ", path)):
        where = f"{MANIFEST}: regions.{index}."
        model = _checked(files, entry, "model", where)
        heights = np.load(io.BytesIO(_checked(files, entry, "expected_height", where)), allow_pickle=False)
        try:
            decode = DecodeConfig(**stored_decode_fields(_require(entry, "decode", dict, where, path)))
        except RetiredSetting as error:
            raise InputError(path, f"{where}decode.{error.field}", f"exported with {error.reason}; export its run "
                                                                   f"again with this version's vc-export") from None
        except TypeError as error:
            raise InputError(path, f"{where}decode", str(error)) from None
        regions.append(RegionEntry(
            name=_require(entry, "name", str, where, path),
            crop_window=tuple(_require(entry, "crop_window", list, where, path)),
            input_size=tuple(_require(entry, "input_size", list, where, path)),
            decode=decode, owned_image_area=_require(entry, "owned_image_area", dict, where, path),
            model=model, expected_height_px=heights,
            precision=str(entry.get("precision", "fp32"))))  # bundles before precisions were all fp32
    if not regions:
        raise InputError(path, f"{MANIFEST}: regions", "the bundle has no regions")
    if "decoder_file" in manifest:  # optional: bundles exported before it lack it, and load as before
        _checked(files, manifest, "decoder_file", f"{MANIFEST}: ")
    facing = None
    if FACING in manifest:  # optional: bundles exported before the facing model lack it, and load as before
        facing = _checked(files, _require(manifest, FACING, dict, f"{MANIFEST}: ", path), "model",
                          f"{MANIFEST}: {FACING}.")
    crop_pose = None
    if CROP_POSE in manifest:  # optional: bundles exported before the keypoint model lack it, and load as before
        crop_pose = _checked(files, _require(manifest, CROP_POSE, dict, f"{MANIFEST}: ", path), "model",
                             f"{MANIFEST}: {CROP_POSE}.")
    return Bundle(path, manifest, regions, _reference(files, manifest, path), _fit_range(manifest, path),
                  tuple(zones_from_manifest(manifest, path)), facing, crop_pose)


def _fit_range(manifest: dict, path: Path) -> FitRange:
    """The reference's fit range, checked; the background's one look when the manifest gives none."""
    entry = manifest.get(REFERENCE)
    if not isinstance(entry, dict) or "fit_range" not in entry:
        return BACKGROUND_ONLY
    try:
        return FitRange.from_dict(entry["fit_range"])
    except (TypeError, ValueError) as error:
        raise InputError(path, f"{MANIFEST}: {REFERENCE}.fit_range", str(error)) from None


def _reference(files: _Files, manifest: dict, path: Path) -> SceneReference | None:
    """The scene fitness reference the manifest names, checked; None when it names none."""
    if REFERENCE not in manifest:
        return None
    where = f"{MANIFEST}: {REFERENCE}."
    entry = _require(manifest, REFERENCE, dict, f"{MANIFEST}: ", path)
    data = _checked(files, entry, "background", where)
    width, height = _require(manifest, "frame_size", list, f"{MANIFEST}: ", path)
    try:
        return SceneReference.from_bytes(data, (int(width), int(height)))
    except ValueError as error:
        raise InputError(path, f"{where}background", f"{entry['background']}: {error}") from None
