"""A camera's frames, read on a thread of their own that keeps only the latest.

Why a thread per camera that keeps one frame: a network slower than the camera must not build a backlog (the
people reported would drift further behind the scene every second), so the reader always replaces the frame
waiting to be run and counts the one it replaced as dropped.

Decoding is OpenCV's FFmpeg backend, which the runtime's ``video`` extra already installs for ``vc-run``: it reads
RTSP (H.264, H.265, MJPEG over RTP), HTTP MJPEG, video files and, through its V4L2 backend, local devices, and it
takes open and read timeouts (``CAP_PROP_OPEN_TIMEOUT_MSEC``, ``CAP_PROP_READ_TIMEOUT_MSEC``), without which a
stalled stream blocks a read for good. PyAV would add a second copy of FFmpeg; GStreamer's Python bindings are not
on PyPI.

A camera that fails to open, stops or stalls is closed and reopened after a back-off that doubles up to a bound and
resets once a frame is read; a video file or folder played once ends its camera. A frame of another size than the
bundle's camera is refused (counted, logged once per change of size, and reported in the health), never run.
"""

from __future__ import annotations

import logging
import os
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vc.deploy.frames import IMAGE_SUFFIXES, read_frame_image
from vc.errors import InputError
from vc.serve.config import CameraSettings

log = logging.getLogger("vc.serve")

#: What each reader reports to the health page, in order of the camera's life.
STATES = ("connecting", "connected", "disconnected", "finished")


@dataclass(frozen=True)
class CapturedFrame:
    number: int  # 1, 2, ... over the camera's whole service, across reconnects
    image: np.ndarray  # (H, W, 3) uint8 RGB
    wall_time: float  # time.time() when it was read
    monotonic: float  # time.monotonic() when it was read


class LatestFrame:
    """A one-frame slot: :meth:`put` replaces an unread frame (a dropped frame), :meth:`take` waits for a new one."""

    def __init__(self) -> None:
        self._frame: CapturedFrame | None = None
        self._ready = threading.Condition()
        self.dropped = 0

    def put(self, frame: CapturedFrame) -> bool:
        """Offer ``frame``; True when it replaced one that was never taken."""
        with self._ready:
            replaced = self._frame is not None
            self.dropped += replaced
            self._frame = frame
            self._ready.notify()
            return replaced

    def take(self, timeout_s: float) -> CapturedFrame | None:
        with self._ready:
            if self._frame is None:
                self._ready.wait(timeout_s)
            frame, self._frame = self._frame, None
            return frame


@dataclass
class ReaderStatus:
    """What the health page says about a camera's reading (read and written under the reader's lock)."""

    state: str = "connecting"
    frames_read: int = 0
    frames_refused: int = 0  # of another size than the bundle's camera
    reconnects: int = 0
    last_frame_monotonic: float | None = None
    last_error: str | None = None
    connected_since: float | None = None
    recent: list[float] = field(default_factory=list)  # monotonic times of the last frames, for frames per second


class _Capture:
    """An opened source: ``read()`` -> RGB frame, or None at its end or on a failed read."""

    def __init__(self, camera: CameraSettings) -> None:
        self.camera = camera
        self.files: Iterator[Path] | None = None
        self.capture = None
        self.fps: float | None = camera.fps
        source = Path(camera.source)
        if not camera.is_stream and not camera.is_device and source.is_dir():
            names = sorted(p for p in source.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
            if not names:
                raise ConnectionError(f"no images in {source}")
            self.files = iter(names)
            return
        import cv2

        reading = camera.reading
        timeouts = [cv2.CAP_PROP_OPEN_TIMEOUT_MSEC, int(reading.open_timeout_s * 1000),
                    cv2.CAP_PROP_READ_TIMEOUT_MSEC, int(reading.read_timeout_s * 1000)]
        backend = cv2.CAP_V4L2 if camera.is_device else cv2.CAP_FFMPEG
        self.capture = cv2.VideoCapture(camera.source, backend, timeouts)
        if not self.capture.isOpened():
            raise ConnectionError(f"cannot open {camera.source}")
        if not camera.is_stream and not camera.is_device and self.fps is None:
            rate = self.capture.get(cv2.CAP_PROP_FPS)
            self.fps = rate if rate and np.isfinite(rate) and rate > 0 else 25.0

    @property
    def paced(self) -> bool:
        """A file or folder is played at its rate; a stream and a device come at theirs."""
        return not (self.camera.is_stream or self.camera.is_device)

    def read(self) -> np.ndarray | None:
        if self.files is not None:
            for path in self.files:  # an unreadable image is skipped, not the end of the folder
                try:
                    return read_frame_image(path)
                except InputError as error:
                    log.warning("camera %s: %s skipped: %s", self.camera.name, path.name, error.reason)
            return None
        ok, bgr = self.capture.read()
        if not ok or bgr is None:
            return None
        if bgr.ndim == 2:
            bgr = np.repeat(bgr[:, :, None], 3, axis=2)
        return np.ascontiguousarray(bgr[:, :, 2::-1])

    def close(self) -> None:
        if self.capture is not None:
            self.capture.release()


#: FFmpeg's options for every capture: RTSP over ``{transport}``, and probing a stream's first 0.5 s (100 kB) rather
#: than its default ~2-3 s, which opened an RTSP camera 2-3 s late and then delivered those seconds' frames at once,
#: stale (measured: MJPEG 2.0 s -> 0.01 s, 1080p H.264 2.8 s -> 0.4 s to open).
FFMPEG_OPTIONS = "rtsp_transport;{transport}|analyzeduration;500000|probesize;100000"


def use_stream_options(transport: str) -> None:
    """FFmpeg's capture options (:data:`FFMPEG_OPTIONS`) for every stream this process opens: OpenCV reads them from
    the environment, where a deployment's own ``OPENCV_FFMPEG_CAPTURE_OPTIONS`` wins."""
    os.environ.setdefault("OPENCV_FFMPEG_CAPTURE_OPTIONS", FFMPEG_OPTIONS.format(transport=transport))


class CameraReader(threading.Thread):
    """Reads ``camera`` into :attr:`latest` until :meth:`stop`; ``frame_size`` (width, height) is the bundle's
    camera's. ``on_event(kind)`` is told ``frame``, ``dropped``, ``refused`` and ``reconnect`` for the metrics."""

    def __init__(self, camera: CameraSettings, frame_size: tuple[int, int],
                 on_event: Callable[[str], None] = lambda kind: None) -> None:
        super().__init__(name=f"read-{camera.name}", daemon=True)
        self.camera, self.frame_size, self.on_event = camera, frame_size, on_event
        self.latest = LatestFrame()
        self.status = ReaderStatus()
        self.lock = threading.Lock()
        self._stopping = threading.Event()
        self._refused_size: tuple[int, int] | None = None
        self._next_due = time.monotonic()  # when a paced source's next frame is read

    def stop(self) -> None:
        self._stopping.set()

    def run(self) -> None:
        backoff = self.camera.reading.backoff_initial_s
        first, looped = True, False
        while not self._stopping.is_set():
            if not first:
                self._set(state="disconnected", reconnects=self.status.reconnects + 1)
                self.on_event("reconnect")
                log.info("camera %s: reopening in %.1f s", self.camera.name, backoff)
                if self._stopping.wait(backoff):
                    break
            first = False
            try:
                capture = _Capture(self.camera)
            except (ConnectionError, OSError) as error:
                self._fault(str(error))
                backoff, looped = min(2 * backoff, self.camera.reading.backoff_max_s), False
                continue
            try:
                read_any, ended = self._read_all(capture, looped)
            finally:
                capture.close()
            if read_any:
                backoff = self.camera.reading.backoff_initial_s
            else:
                backoff = min(2 * backoff, self.camera.reading.backoff_max_s)
            if ended and not self.camera.loop:
                self._set(state="finished")
                log.info("camera %s: %s ended", self.camera.name, self.camera.source)
                return
            first = looped = ended  # a looped file starts again at once: its end is no fault
        self._set(state="disconnected")  # stopped (a finished source returned above)

    def _read_all(self, capture: _Capture, looped: bool) -> tuple[bool, bool]:
        """Read frames until the source ends or fails; (whether any frame was read, whether it ended as a file
        does rather than failed). A looped file read again from its start (``looped``) is not logged again: a
        one-image file looped at 1 frame/s would log every second."""
        self._set(state="connected", connected_since=time.monotonic(), last_error=None)
        (log.debug if looped else log.info)("camera %s: reading %s", self.camera.name, self.camera.source)
        interval = 1.0 / capture.fps if capture.paced and capture.fps else 0.0
        read_any = False
        while not self._stopping.is_set():
            image = capture.read()
            if image is None:
                if capture.paced:
                    return read_any, True
                self._fault(f"no frame from {self.camera.source} within {self.camera.reading.read_timeout_s:g} s "
                            f"or the stream ended")
                return read_any, False
            read_any = True
            if interval:  # delivered at its time; the pace runs on across a looped file's restarts
                if self._stopping.wait(max(0.0, self._next_due - time.monotonic())):
                    break
                self._next_due = max(self._next_due + interval, time.monotonic() - interval)
            self._deliver(image)
        return read_any, False

    def _deliver(self, image: np.ndarray) -> None:
        now = time.monotonic()
        size = (image.shape[1], image.shape[0])
        if size != self.frame_size:
            with self.lock:
                self.status.frames_refused += 1
                self.status.last_error = (f"frames of {size[0]}x{size[1]}, the bundle's camera is "
                                          f"{self.frame_size[0]}x{self.frame_size[1]}: not run")
            if size != self._refused_size:
                log.error("camera %s: %s", self.camera.name, self.status.last_error)
                self._refused_size = size
            self.on_event("refused")
            return
        if self._refused_size is not None:
            log.info("camera %s: frames of the bundle's size again", self.camera.name)
            self._refused_size = None
        with self.lock:
            self.status.frames_read += 1
            self.status.last_frame_monotonic = now
            self.status.last_error = None
            self.status.recent = [t for t in self.status.recent if t > now - 5.0][-100:] + [now]
            number = self.status.frames_read
        self.on_event("frame")
        if self.latest.put(CapturedFrame(number, image, time.time(), now)):
            self.on_event("dropped")

    def _fault(self, message: str) -> None:
        with self.lock:
            self.status.last_error = message
        log.warning("camera %s: %s", self.camera.name, message)

    def _set(self, **fields: object) -> None:
        with self.lock:
            for name, value in fields.items():
                setattr(self.status, name, value)

    def snapshot(self) -> ReaderStatus:
        with self.lock:
            return ReaderStatus(**{name: getattr(self.status, name) for name in ReaderStatus.__dataclass_fields__})
