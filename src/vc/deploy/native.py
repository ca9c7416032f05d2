"""The C decoder (``native/vc_decode.c``: :mod:`vc.deploy.decode`'s algorithm in C99, libm only) from Python, through
ctypes, when it is built; numpy's decoder stays the reference and the fallback.

``make install`` builds it beside its sources (``native/libvc_decode.so``, with ``cc``: :func:`build`); the runtime
wheel ships the sources, and ``python -m vc.deploy.native`` builds them where the wheel is installed.
:envvar:`VC_DECODER_LIBRARY` names another build (the tests load AddressSanitizer and UndefinedBehaviorSanitizer
builds this way). On the same float32 heat maps both decoders report the same people: count equal, boxes and
keypoints within 1e-3 px, scores equal (tests/test_native_decode.py, on random, degenerate and hostile maps and on
real frames); they refuse the same heat maps (:func:`vc.deploy.decode.check_decodable`).
"""

from __future__ import annotations

import ctypes
import functools
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vc.deploy.decode import (
    UPRIGHT_PRIOR,
    DecodeConfig,
    DecodedPerson,
    UprightPrior,
    check_decodable,
    one_head_each,
    with_heads_added,
)
from vc.deploy.heatmaps import HEAD_CHANNELS
from vc.errors import InputError
from vc.keypoints import COCO_KEYPOINTS

#: Where the sources lie, and the library :func:`build` writes there.
SOURCES = Path(__file__).resolve().parent / "native"
LIBRARY = SOURCES / "libvc_decode.so"
#: Names a build of the library to load instead of :data:`LIBRARY`.
LIBRARY_VARIABLE = "VC_DECODER_LIBRARY"
#: The decoders a runtime can use; "c" only where the library is built.
DECODERS = ("c", "numpy")
#: The compiler's flags: C99, and no fused multiply-adds, whose rounding numpy's arithmetic does not have.
C_FLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-ffp-contract=off", "-Wall", "-Wextra", "-pedantic")
#: The sanitizers' flags (:func:`build` with ``sanitize=True``).
SANITIZER_FLAGS = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g")

_KEYPOINTS, _PAIRS = len(COCO_KEYPOINTS), 8


class _Config(ctypes.Structure):
    _fields_ = [("stride", ctypes.c_int), ("centre_threshold", ctypes.c_double),
                ("keypoint_threshold", ctypes.c_double), ("mask_threshold", ctypes.c_double),
                ("search_sigma", ctypes.c_double), ("default_height_px", ctypes.c_double),
                ("max_people", ctypes.c_int), ("min_centre_separation", ctypes.c_double),
                ("reach_sideways", ctypes.c_double), ("reach_vertical", ctypes.c_double),
                ("min_width", ctypes.c_double), ("side_margin", ctypes.c_double),
                ("keypoint_height_range", ctypes.c_double), ("keypoint_peak_floor", ctypes.c_double),
                ("vote_support", ctypes.c_double), ("vote_separation", ctypes.c_double),
                ("prior_offsets", ctypes.c_double * _KEYPOINTS), ("prior_lower_ankle", ctypes.c_double)]


class _Person(ctypes.Structure):
    _fields_ = [("score", ctypes.c_double), ("centre", ctypes.c_double * 2),
                ("keypoints", ctypes.c_double * (_KEYPOINTS * 3)), ("box", ctypes.c_double * 4),
                ("pair_handedness", ctypes.c_float * _PAIRS), ("weak", ctypes.c_int), ("head_found", ctypes.c_int)]


class _Region(ctypes.Structure):
    _fields_ = [("name", ctypes.c_char * 64), ("crop_window", ctypes.c_int * 4), ("input_size", ctypes.c_int * 2),
                ("channels", ctypes.c_int), ("heatmap_size", ctypes.c_int * 2), ("config", _Config),
                ("expected_height_px", ctypes.POINTER(ctypes.c_float))]


class _Bundle(ctypes.Structure):
    _fields_ = [("version", ctypes.c_int), ("frame_size", ctypes.c_int * 2), ("region_count", ctypes.c_int),
                ("regions", ctypes.POINTER(_Region))]


@dataclass(frozen=True)
class DecoderFileRegion:
    """One region of a bundle's decoder file as the C decoder reads it (:func:`read_decoder_file`)."""

    name: str
    crop_window: tuple[int, int, int, int]
    input_size: tuple[int, int]
    channels: int
    config: DecodeConfig
    prior: UprightPrior
    expected_height_px: np.ndarray  # (h, w) float32


class DecoderNotBuilt(RuntimeError):
    """The C decoder was asked for where its library is not built (or does not load)."""


def library_path() -> Path:
    """The library loaded: :envvar:`VC_DECODER_LIBRARY` where set, else :data:`LIBRARY`."""
    return Path(os.environ.get(LIBRARY_VARIABLE) or LIBRARY)


@functools.cache
def _library(path: Path) -> ctypes.CDLL | None:
    if not path.is_file():
        return None
    try:
        library = ctypes.CDLL(str(path))
    except OSError:
        return None
    library.vc_decode.restype = ctypes.c_int
    library.vc_decode.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.POINTER(_Config),
                                  ctypes.c_void_p, ctypes.c_double, ctypes.POINTER(_Person), ctypes.c_int,
                                  ctypes.POINTER(ctypes.c_int), ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    library.vc_bundle_read.restype = ctypes.c_int
    library.vc_bundle_read.argtypes = [ctypes.c_char_p, ctypes.POINTER(_Bundle), ctypes.POINTER(ctypes.c_int)]
    library.vc_bundle_free.restype = None
    library.vc_bundle_free.argtypes = [ctypes.POINTER(_Bundle)]
    library.vc_status_message.restype = ctypes.c_char_p
    library.vc_status_message.argtypes = [ctypes.c_int]
    return library


def available() -> bool:
    """Whether the C decoder is built and loads."""
    return _library(library_path()) is not None


def default_decoder() -> str:
    """The decoder a runtime uses unless told: C where built, else numpy."""
    return "c" if available() else "numpy"


def checked_decoder(name: str | None) -> str:
    """``name`` (None: :func:`default_decoder`) if it is one of :data:`DECODERS` and usable here; an InputError
    naming the field and why otherwise."""
    name = default_decoder() if name is None else name
    if name not in DECODERS:
        raise InputError(None, "decoder", f"{name!r} is not one of {', '.join(DECODERS)}")
    if name == "c" and not available():
        raise InputError(None, "decoder", f"the C decoder is not built here ({library_path()} is missing or does "
                                          f"not load): run `python -m vc.deploy.native` (needs a C compiler), or use "
                                          f"the numpy decoder")
    return name


def _config(config: DecodeConfig, prior: UprightPrior) -> _Config:
    values = {name: getattr(config, name) for name, _ in _Config._fields_ if hasattr(config, name)}
    if values["vote_separation"] is None:
        values["vote_separation"] = float("nan")
    return _Config(**values, prior_offsets=(ctypes.c_double * _KEYPOINTS)(*prior.offsets),
                   prior_lower_ankle=prior.lower_ankle)


def decode(heatmaps: np.ndarray, config: DecodeConfig | None = None,
           expected_height_px: np.ndarray | None = None, weak_above: float | None = None,
           prior: UprightPrior = UPRIGHT_PRIOR) -> list[DecodedPerson]:
    """:func:`vc.deploy.decode.decode` with the C decoder's readings: the same arguments, the same people (float32
    heat maps; others are converted to float32 first) and the same refusals. Raises :class:`DecoderNotBuilt` where
    the library is not built."""
    config = DecodeConfig() if config is None else config
    readings = decode_readings(heatmaps, config, expected_height_px, weak_above, prior)
    return one_head_each(with_heads_added(readings, config.max_people))


def decode_readings(heatmaps: np.ndarray, config: DecodeConfig | None = None,
                    expected_height_px: np.ndarray | None = None, weak_above: float | None = None,
                    prior: UprightPrior = UPRIGHT_PRIOR) -> list[DecodedPerson]:
    """:func:`vc.deploy.decode.decode_readings` in C (as :func:`decode`)."""
    config = DecodeConfig() if config is None else config
    library = _library(library_path())
    if library is None:
        raise DecoderNotBuilt(f"the C decoder is not built ({library_path()})")
    maps = np.ascontiguousarray(heatmaps, np.float32)
    if maps.ndim != 3:
        raise ValueError(f"heat maps of shape {maps.shape}, not (channels, height, width)")
    channels, height, width = maps.shape
    heights = None if expected_height_px is None else np.ascontiguousarray(expected_height_px, np.float32)
    if heights is not None and heights.shape != (height, width):
        check_decodable(maps, heights)  # raises, naming the shapes
    capacity = max(config.max_people * (2 if channels == HEAD_CHANNELS else 1), 1)
    people = (_Person * capacity)()
    count = ctypes.c_int(0)
    strong_owner = np.empty((height, width), np.int32)
    weak_owner = np.empty((height, width), np.int32)
    head_owner = np.empty((height, width), np.int32)
    status = library.vc_decode(maps.ctypes.data, channels, height, width, ctypes.byref(_config(config, prior)),
                               None if heights is None else heights.ctypes.data,
                               float("nan") if weak_above is None else float(weak_above), people, capacity,
                               ctypes.byref(count), strong_owner.ctypes.data, weak_owner.ctypes.data,
                               head_owner.ctypes.data)
    if status != 0:
        check_decodable(maps, heights)  # the numpy decoder's own words for a refusal both make
        raise ValueError(f"the C decoder refused the heat maps: {library.vc_status_message(status).decode()}")
    decoded = []
    for index in range(count.value):
        person = people[index]
        owner = head_owner if person.head_found else weak_owner if person.weak else strong_owner
        decoded.append(DecodedPerson(
            score=person.score, centre=np.array(person.centre[:]),
            keypoints=np.array(person.keypoints[:]).reshape(_KEYPOINTS, 3), box=np.array(person.box[:]),
            mask_cells=owner == index, pair_handedness=np.array(person.pair_handedness[:], np.float32),
            weak=bool(person.weak), head_found=bool(person.head_found)))
    return decoded


def read_decoder_file(path: Path) -> tuple[tuple[int, int], list[DecoderFileRegion]]:
    """A bundle's decoder file (:mod:`vc.deploy.decoder_file`) as the C decoder reads it: the frame size and the
    regions. A file it refuses raises ValueError naming the line at fault."""
    library = _library(library_path())
    if library is None:
        raise DecoderNotBuilt(f"the C decoder is not built ({library_path()})")
    bundle, line = _Bundle(), ctypes.c_int(0)
    status = library.vc_bundle_read(str(path).encode(), ctypes.byref(bundle), ctypes.byref(line))
    if status != 0:
        raise ValueError(f"{path}, line {line.value}: {library.vc_status_message(status).decode()}")
    try:
        regions = []
        for index in range(bundle.region_count):
            region = bundle.regions[index]
            width, height = region.heatmap_size
            config = {name: getattr(region.config, name) for name, _ in _Config._fields_
                      if name not in ("prior_offsets", "prior_lower_ankle")}
            config["vote_separation"] = None if np.isnan(config["vote_separation"]) else config["vote_separation"]
            regions.append(DecoderFileRegion(
                region.name.decode(), tuple(region.crop_window), tuple(region.input_size), region.channels,
                DecodeConfig(**config), UprightPrior(np.array(region.config.prior_offsets[:]),
                                                     region.config.prior_lower_ankle),
                np.ctypeslib.as_array(region.expected_height_px, (height, width)).copy()))
        return (bundle.frame_size[0], bundle.frame_size[1]), regions
    finally:
        library.vc_bundle_free(ctypes.byref(bundle))


def build(output: Path = LIBRARY, sanitize: bool = False, compiler: str | None = None) -> Path:
    """Compiles the C decoder into the shared library ``output`` (with the sanitizers: :data:`SANITIZER_FLAGS`)
    with ``compiler`` (default: :envvar:`CC`, else ``cc``); a failed compile raises CalledProcessError with the
    compiler's words."""
    compiler = compiler or os.environ.get("CC", "cc")
    flags = (*C_FLAGS, *(SANITIZER_FLAGS if sanitize else ()))
    output = Path(output)
    temporary = output.with_name(output.name + ".tmp")  # a failed compile leaves the last build as it was
    subprocess.run([compiler, *flags, "-o", str(temporary), *map(str, sorted(SOURCES.glob("vc_*.c"))), "-lm"],
                   check=True, capture_output=True, text=True)
    temporary.replace(output)
    return output


if __name__ == "__main__":
    try:
        print(f"built {build()}")
    except subprocess.CalledProcessError as error:
        print(error.stderr, file=sys.stderr)
        sys.exit(1)
