"""File output that never leaves a half-written file behind, and image I/O through OpenImageIO.

Everything a stage writes goes to a temporary name in the destination folder first and is renamed into place
(atomic on POSIX), so a crash or Ctrl-C leaves either the old file or the new one, never a torn one.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import glob
import json
import os
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from vc.errors import NO_ROOM, InputError, OutputError


@atexit.register
def _release_colour_openimageio_objects() -> None:
    """colour-science keeps OpenImageIO type objects in module globals (colour.io.image); when torch is loaded
    too, they outlive OpenImageIO's nanobind module at shutdown and it prints a "leaked instances" report on every
    exit. Dropping those references while the interpreter is still whole keeps stderr clean."""
    image_module = sys.modules.get("colour.io.image")
    if image_module is None:
        return
    getattr(image_module, "MAPPING_BIT_DEPTH", {}).clear()
    for name in ("DOUBLE", "FLOAT", "HALF", "UINT8", "UINT16", "ImageSpec"):
        image_module.__dict__.pop(name, None)


@contextlib.contextmanager
def atomic_path(destination: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``destination``; rename it into place only if the block succeeds."""
    destination = Path(destination)
    try:
        destination.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(destination.parent, "", f"cannot create output folder ({error.strerror})") from None
    if not os.access(destination.parent, os.W_OK):
        raise InputError(destination.parent, "", "output folder is not writable")
    prefix, suffix = f".{destination.name}.", ".tmp" + destination.suffix
    _remove_stale_temporaries(destination.parent, prefix, suffix)
    try:
        handle, temporary = tempfile.mkstemp(prefix=prefix, suffix=suffix, dir=destination.parent)
    except OSError as error:
        raise OutputError(destination, error.strerror) from None
    os.close(handle)
    os.chmod(temporary, 0o644)  # mkstemp's 0600 is for the temporary; the file it becomes is an ordinary output
    temporary_path = Path(temporary)
    try:
        yield temporary_path
        os.replace(temporary_path, destination)
    except OSError as error:
        if error.errno in NO_ROOM or error.errno in (errno.EIO, errno.EROFS):
            raise OutputError(destination, error.strerror) from None
        raise
    finally:
        temporary_path.unlink(missing_ok=True)


def _remove_stale_temporaries(folder: Path, prefix: str, suffix: str) -> None:
    """Temporaries of the same output that a run killed mid-write (SIGKILL, power loss) left behind. One output
    has one writer at a time, so any such file is stale."""
    for stale in folder.glob(f"{glob.escape(prefix)}*{glob.escape(suffix)}"):
        if stale.is_dir() and not stale.is_symlink():
            shutil.rmtree(stale, ignore_errors=True)
        else:
            stale.unlink(missing_ok=True)


@contextlib.contextmanager
def atomic_directory(destination: str | Path) -> Iterator[Path]:
    """Yield a staging folder beside ``destination``; it replaces ``destination`` only if the block succeeds, so a
    reader sees the old folder or the complete new one, never a half-written one."""
    destination = Path(destination)
    prefix = f".{destination.name}."
    try:
        destination.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale_temporaries(destination.parent, prefix, ".tmp")
        staging = Path(tempfile.mkdtemp(prefix=prefix, suffix=".tmp", dir=destination.parent))
        staging.chmod(0o755)
    except OSError as error:
        if error.errno in NO_ROOM:
            raise OutputError(destination, error.strerror) from None
        raise InputError(destination.parent, "", f"cannot create output folder ({error.strerror})") from None
    try:
        yield staging
        if destination.is_dir() and not destination.is_symlink():
            shutil.rmtree(destination)
        elif destination.exists():
            raise InputError(destination, "", "exists and is not a folder")
        staging.rename(destination)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def write_json(destination: str | Path, data: object) -> None:
    with atomic_path(destination) as temporary:
        temporary.write_text(json.dumps(data, indent=2, sort_keys=False) + "\n")


def _open_image(path: Path) -> oiio.ImageInput:
    if not path.is_file():
        raise InputError(path, "", "image file not found")
    image_input = oiio.ImageInput.open(str(path))
    if image_input is None:
        raise InputError(path, "", f"cannot read image ({oiio.geterror().strip() or 'unknown format'})")
    return image_input


def read_image(path: str | Path) -> np.ndarray:
    """An image file as an (H, W, 3) uint8 array (grey is expanded, alpha dropped)."""
    image_input = _open_image(Path(path))
    try:
        pixels = image_input.read_image(oiio.UINT8)
    finally:
        image_input.close()
    if pixels is not None and pixels.ndim == 2:
        pixels = pixels[:, :, None]
    if pixels is None or pixels.ndim != 3:
        raise InputError(path, "", "cannot decode image pixels")
    if pixels.shape[2] == 1:
        pixels = np.repeat(pixels, 3, axis=2)
    return np.ascontiguousarray(pixels[:, :, :3])


def image_size(path: str | Path) -> tuple[int, int]:
    """(width, height) from the file header, without decoding the pixels."""
    image_input = _open_image(Path(path))
    spec = image_input.spec()
    image_input.close()
    return spec.width, spec.height


#: zlib level for PNGs written in bulk (datasets): 4x faster than OpenImageIO's default 6, files ~25% larger.
FAST_PNG_COMPRESSION = 1


def write_image(destination: str | Path, pixels: np.ndarray, png_compression: int | None = None) -> None:
    """Write an (H, W, C) uint8 image (PNG, JPEG… by extension) atomically.

    ``png_compression`` (0-9) overrides OpenImageIO's default zlib level for PNG files.
    """
    pixels = np.ascontiguousarray(pixels)
    if pixels.dtype != np.uint8:
        raise TypeError(f"write_image expects uint8 pixels, got {pixels.dtype}")
    height, width = pixels.shape[:2]
    channels = pixels.shape[2] if pixels.ndim == 3 else 1
    destination = Path(destination)
    with atomic_path(destination) as temporary:
        # OpenImageIO picks the format from the extension: keep the real one at the end of the temporary name.
        output = oiio.ImageOutput.create(str(destination))
        if output is None:
            raise InputError(destination, "", f"unsupported image format ({oiio.geterror().strip()})")
        spec = oiio.ImageSpec(width, height, channels, oiio.UINT8)
        if png_compression is not None:
            spec.attribute("png:compressionLevel", int(png_compression))
        written = output.open(str(temporary), spec) and output.write_image(pixels)
        # OpenImageIO reports a short write (a full disk) only through geterror: write_image still says True.
        message = output.geterror()
        closed = output.close()
        if not (written and closed) or message:
            reason = (message or oiio.geterror() or "the image library failed").splitlines()[0].strip()
            raise OutputError(destination, reason)
