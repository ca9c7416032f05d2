"""``vc-serve``'s configuration: the cameras, the broker, the event queue and the health server, typed and read from
one YAML file.

Every default lives here and nowhere else. Paths are relative to the configuration file, so a deployment folder
(config, bundles, queue) can move as a whole. A bad file is refused before anything starts, with one
:class:`~vc.errors.InputError` naming the file and the field.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator, model_validator

from vc.deploy.engines import DEFAULT_ENGINE, ENGINES
from vc.deploy.runtime import DEFAULT_UNFIT, UNFIT_SETTINGS
from vc.errors import InputError

#: Source schemes read as network streams (FFmpeg through OpenCV); anything else is a path.
STREAM_SCHEMES = ("rtsp://", "rtsps://", "http://", "https://")


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class ReadingSettings(_Section):
    """How a camera's frames are read (:mod:`vc.serve.sources`)."""

    # A stream that does not open within this is retried (with back-off); FFmpeg's own default waits ~30 s.
    open_timeout_s: float = Field(10.0, gt=0)
    # A stream that yields no frame for this long is closed and reopened: a stalled camera is a lost camera.
    read_timeout_s: float = Field(5.0, gt=0)
    # The first retry waits this long, each further one twice as long, up to backoff_max_s; a frame read resets it.
    backoff_initial_s: float = Field(0.5, gt=0)
    backoff_max_s: float = Field(30.0, gt=0)

    @model_validator(mode="after")
    def _backoff_grows(self) -> ReadingSettings:
        if self.backoff_max_s < self.backoff_initial_s:
            raise ValueError("backoff_max_s must be at least backoff_initial_s")
        return self


class CameraSettings(_Section):
    """One camera: its bundle, where its frames come from, and how they are read and run."""

    name: str = Field(pattern=r"^[A-Za-z0-9_-]+$")  # part of the MQTT topic and the metrics' labels
    bundle: Path
    # rtsp://, http(s):// (MJPEG), a video file, a folder of images, or a V4L2 device (/dev/videoN)
    source: str = Field(min_length=1)
    # A video file or folder played as a camera: once, or from the start again at its end.
    loop: bool = False
    # A video file or folder is paced at this rate (default: a video's own; a folder needs it). A live source comes
    # at its own rate.
    fps: float | None = Field(None, gt=0)
    public_key: Path | None = None  # load the bundle only if its manifest is signed by this Ed25519 key (PEM)
    unfit: str = DEFAULT_UNFIT
    threads: int = Field(1, ge=1)  # the engine's threads for this camera's networks
    engine: str = DEFAULT_ENGINE  # what runs the networks: onnxruntime or openvino (vc.deploy.engines)
    reading: ReadingSettings = ReadingSettings()

    @field_validator("unfit", "engine")
    @classmethod
    def _one_of_its_choices(cls, value: str, info: ValidationInfo) -> str:
        choices = {"unfit": UNFIT_SETTINGS, "engine": ENGINES}[info.field_name]
        if value not in choices:
            raise ValueError(f"{value!r} is not one of {', '.join(choices)}")
        return value

    @property
    def is_stream(self) -> bool:
        return self.source.startswith(STREAM_SCHEMES)

    @property
    def is_device(self) -> bool:
        return re.fullmatch(r"/dev/video\d+", self.source) is not None


class MqttSettings(_Section):
    """The broker the events go to (:mod:`vc.serve.mqtt`)."""

    host: str = "localhost"
    port: int = Field(1883, ge=1, le=65535)
    topic_prefix: str = Field("vc", pattern=r"^[^#+]+$")  # events go to <prefix>/<camera>/events
    client_id: str | None = None  # default: vc-serve-<host name>; a fixed id keeps the broker's session
    username: str | None = None
    password: str | None = None
    keepalive_s: int = Field(30, ge=5)
    # Events published and not yet acknowledged at once: enough to keep a link busy, few enough that a broker
    # outage leaves few in doubt.
    max_in_flight: int = Field(20, ge=1, le=65535)


class EventSettings(_Section):
    """Which events are made, and where they wait for the broker (:mod:`vc.serve.events`, :mod:`vc.serve.queue`)."""

    queue: Path = Path("events.sqlite")
    # Events kept while the broker is unreachable; beyond it the oldest go (logged and counted). At ~10 events a
    # second (a busy PETS09 camera) 100 000 hold about three hours.
    queue_limit: int = Field(100_000, ge=1)
    # A track's position is published at most this often (new, end and zone changes are published at once).
    update_interval_s: float = Field(1.0, ge=0)
    # JSON Lines copies of the events, in rotating files in this folder (None: none).
    jsonl: Path | None = None
    jsonl_max_bytes: int = Field(10_000_000, ge=1024)
    jsonl_backups: int = Field(5, ge=1)


class HttpSettings(_Section):
    """Where ``/healthz`` and ``/metrics`` are served (:mod:`vc.serve.http`)."""

    host: str = "0.0.0.0"
    port: int = Field(8080, ge=0, le=65535)  # 0: any free port (tests)
    # A camera whose last frame is older than this is stale (/healthz answers 503). None: twice its read timeout.
    stale_after_s: float | None = Field(None, gt=0)


class ServeConfig(_Section):
    """The whole ``vc-serve`` configuration file."""

    cameras: list[CameraSettings] = Field(min_length=1)
    mqtt: MqttSettings = MqttSettings()
    events: EventSettings = EventSettings()
    http: HttpSettings = HttpSettings()
    # RTSP over TCP: no frames torn by lost UDP packets, at the cost of latency on a lossy link. One setting for the
    # process: FFmpeg takes it from the environment (OPENCV_FFMPEG_CAPTURE_OPTIONS, which, when set, wins).
    rtsp_transport: Literal["tcp", "udp"] = "tcp"

    @model_validator(mode="after")
    def _unique_names(self) -> ServeConfig:
        names = [camera.name for camera in self.cameras]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise ValueError(f"camera names must be unique: {', '.join(repeated)} repeated")
        return self

    def stale_after_s(self, camera: CameraSettings) -> float:
        return self.http.stale_after_s or 2.0 * camera.reading.read_timeout_s


def _resolved(config: ServeConfig, folder: Path) -> ServeConfig:
    """Paths relative to the configuration file's folder made absolute."""

    def path(value: Path | None) -> Path | None:
        return None if value is None else (folder / value).resolve()

    cameras = []
    for camera in config.cameras:
        source = camera.source
        if not camera.is_stream and not camera.is_device:
            source = str(path(Path(source)))
        cameras.append(camera.model_copy(update={"bundle": path(camera.bundle), "source": source,
                                                 "public_key": path(camera.public_key)}))
    events = config.events.model_copy(update={"queue": path(config.events.queue), "jsonl": path(config.events.jsonl)})
    return config.model_copy(update={"cameras": cameras, "events": events})


def _check_files(config: ServeConfig, path: Path) -> None:
    """What can be known before starting: bundles and file sources exist, a folder has a rate."""
    for index, camera in enumerate(config.cameras):
        where = f"cameras.{index}"
        if not camera.bundle.exists():
            raise InputError(path, f"{where}.bundle", f"not found: {camera.bundle}")
        if camera.public_key is not None and not camera.public_key.is_file():
            raise InputError(path, f"{where}.public_key", f"not found: {camera.public_key}")
        if camera.is_stream or camera.is_device:
            continue
        source = Path(camera.source)
        if not source.exists():
            raise InputError(path, f"{where}.source", f"not found: {source} (expected rtsp://, http(s)://, a video "
                                                      f"file, a folder of images or /dev/videoN)")
        if source.is_dir() and camera.fps is None:
            raise InputError(path, f"{where}.fps", "a folder of images is played at a rate: give fps")


def read_serve_config(path: Path) -> ServeConfig:
    """The configuration in ``path``, validated, paths resolved; bad input raises :class:`InputError`."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as error:
        raise InputError(path, "", f"cannot read the configuration ({error.strerror})") from None
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else ""
        raise InputError(path, where, f"not valid YAML ({getattr(error, 'problem', None) or error})") from None
    if not isinstance(data, dict):
        raise InputError(path, "", "expected a mapping with cameras (and optionally mqtt, events, http)")
    try:
        config = ServeConfig.model_validate(data)
    except ValidationError as error:
        problem = error.errors(include_url=False)[0]
        where = ".".join(str(part) for part in problem["loc"]) or "(top level)"
        message = problem["msg"].removeprefix("Value error, ")
        if problem["type"] == "extra_forbidden":
            message = "unknown field (check the spelling)"
        elif problem["type"] == "missing":
            message = "missing required field"
        raise InputError(path, where, message) from None
    config = _resolved(config, path.resolve().parent)
    _check_files(config, path)
    return config
