"""Frames from an image, a folder of images or a video file, numbered from 1 as the MOT ground truth numbers them.

One reader for ``vc-run``, ``vc-eval`` and an appliance: all take "an image, a folder of frames or a video",
select frames with ``first:last:step`` (1-based, inclusive) and must refuse an empty or unreadable input with one
clear error before anything is written.

Decoding goes through OpenCV, imported only when frames are read: the appliance runtime installs it with its
``video`` extra (``visual-compiler-runtime[video]``), and a runtime that is handed frames by its camera needs none.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vc.errors import InputError

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"}


@dataclass(frozen=True)
class FrameRange:
    """Frames ``first`` to ``last`` (1-based, inclusive; None: to the end), every ``step``-th."""

    first: int = 1
    last: int | None = None
    step: int = 1

    def __contains__(self, number: int) -> bool:
        return number >= self.first and (self.last is None or number <= self.last) \
            and (number - self.first) % self.step == 0

    def count(self, available: int) -> int:
        last = available if self.last is None else min(self.last, available)
        return max(0, (last - self.first) // self.step + 1) if last >= self.first else 0

    @classmethod
    def parse(cls, text: str) -> FrameRange:
        """``first:last:step`` with any part left empty (``1:400:5``, ``::10``, ``100:``)."""
        parts = text.split(":")
        if len(parts) > 3:
            raise argparse.ArgumentTypeError(f"expected first:last:step, got {text!r}")
        try:
            values = [int(part) if part.strip() else None for part in parts] + [None] * (3 - len(parts))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected integers in first:last:step, got {text!r}") from None
        first = 1 if values[0] is None else values[0]
        step = 1 if values[2] is None else values[2]
        last = values[1]
        if first < 1 or step < 1 or (last is not None and last < first):
            raise argparse.ArgumentTypeError(f"need 1 <= first <= last and step >= 1, got {text!r}")
        return cls(first, last, step)


def _opencv():
    try:
        import cv2
    except ImportError:
        raise InputError(None, "frames", "reading images and videos needs OpenCV: install the runtime's 'video' "
                                         "extra (pip install 'visual-compiler-runtime[video]')") from None
    return cv2


def read_frame_image(path: Path) -> np.ndarray:
    """An image file as an (H, W, 3) uint8 RGB frame (grey expanded, alpha dropped, deeper images scaled to 8 bits),
    its pixels as stored: an EXIF orientation is not applied, so frames keep the size of the camera's frames."""
    cv2 = _opencv()
    bgr = cv2.imread(str(path), cv2.IMREAD_COLOR | cv2.IMREAD_IGNORE_ORIENTATION)
    if bgr is None:
        raise InputError(path, "", "cannot decode as an image (unknown format or corrupt file)")
    return np.ascontiguousarray(bgr[:, :, ::-1])


@dataclass(frozen=True)
class Frame:
    number: int  # 1-based position in the input
    name: str  # file name for images, frame number for video
    image: np.ndarray  # (H, W, 3) uint8 RGB


class FrameSource:
    """The selected frames of ``path``: an image file, a folder of image files (sorted by name) or a video."""

    def __init__(self, path: Path, frames: FrameRange = FrameRange()) -> None:
        self.path, self.frames = Path(path), frames
        if self.path.is_dir():
            self.kind = "folder"
            self.files = sorted(p for p in self.path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
            if not self.files:
                raise InputError(self.path, "", f"no image files ({', '.join(sorted(IMAGE_SUFFIXES))}) in this folder")
            available = len(self.files)
        elif self.path.suffix.lower() in IMAGE_SUFFIXES:
            self.kind, self.files, available = "image", [self.path], 1
        elif self.path.is_file():
            self.kind, self.files = "video", []
            available = self._video_length()
        else:
            raise InputError(self.path, "", "no such file or folder")
        self.count = frames.count(available)
        if self.count == 0:
            raise InputError(self.path, "frames", f"the selection {frames.first}:{frames.last or ''}:{frames.step} "
                                                  f"holds none of its {available} frame(s)")

    def _open_video(self):
        capture = _opencv().VideoCapture(str(self.path))
        if not capture.isOpened():
            raise InputError(self.path, "", "cannot open as a video (unknown format or corrupt file)")
        return capture

    def _video_length(self) -> int:
        capture = self._open_video()
        try:
            ok, _ = capture.read()
            if not ok:
                raise InputError(self.path, "", "the video holds no readable frame")
            self.fps = capture.get(_opencv().CAP_PROP_FPS) or 10.0
            return max(int(capture.get(_opencv().CAP_PROP_FRAME_COUNT)), 1)
        finally:
            capture.release()

    def __len__(self) -> int:
        return self.count

    def __iter__(self) -> Iterator[Frame]:
        if self.kind != "video":
            for number, file in enumerate(self.files, start=1):
                if number in self.frames:
                    yield Frame(number, file.name, read_frame_image(file))
            return
        capture = self._open_video()
        try:
            number = 0
            while self.frames.last is None or number < self.frames.last:
                number += 1
                if number not in self.frames:
                    if not capture.grab():
                        return
                    continue
                ok, bgr = capture.read()
                if not ok:
                    return
                yield Frame(number, f"{number:06d}", np.ascontiguousarray(bgr[:, :, ::-1]))
        finally:
            capture.release()
