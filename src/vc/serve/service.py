"""``vc-serve``'s service: several cameras, each read, run, tracked and turned into events, one broker, one health
server, for months.

Per camera, two threads: its reader (:mod:`vc.serve.sources`, keeping only the latest frame) and its worker, which
takes that frame, runs the bundle (:class:`~vc.deploy.runtime.Runtime`, scene fitness included), tracks the people
(:class:`~vc.deploy.tracking.Tracker`, on the frames' capture times) and makes the tracks' events
(:mod:`vc.serve.events`). Events go to the on-disk queue (:mod:`vc.serve.queue`), from which the publisher
(:mod:`vc.serve.mqtt`) delivers them, and optionally to rotating JSON Lines files.

Faults stay inside their camera: a frame whose processing raises is logged with its traceback, counted
(``vc_frame_faults``) and named in the health, and the worker takes the next frame. A camera that goes silent ends
its tracks once the tracker would (``max_gap_s``). A camera that stops showing its scene says so
(:class:`SceneWatch`): each frame's scene fitness is counted by state (``vc_frames_fitness``), the health gives the
camera's scene state, since when, and the view's registration, and a change of state or registration that holds for
:data:`SETTLED_FRAMES` frames is logged once (a warning when the camera cannot see: covered, dark, moved ...).

:meth:`Service.stop` (SIGTERM, SIGINT) stops the readers, lets each worker finish the frame in flight and end its
live tracks (``reason: shutdown``), waits briefly for the broker to acknowledge what is in flight, and closes the
queue: whatever the broker has not acknowledged is on disk, and delivered first after a restart.
"""

from __future__ import annotations

import json
import logging
import logging.handlers
import threading
import time
import traceback

from vc.deploy.bundle import Bundle, load_bundle
from vc.deploy.fitness import UNFIT_STATES, FrameFitness
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker
from vc.deploy.zones import SceneZones
from vc.serve.config import CameraSettings, ServeConfig
from vc.serve.events import TrackEvents
from vc.serve.health import HealthServer, ServiceMetrics, age_s, frames_per_second
from vc.serve.mqtt import Publisher
from vc.serve.queue import EventQueue
from vc.serve.sources import CameraReader, CapturedFrame, use_stream_options

log = logging.getLogger("vc.serve")

#: How long a stopping service waits for the broker to acknowledge the events in flight (the rest stay queued).
DRAIN_S = 2.0
#: A camera's scene state or registration is logged once it has held this many frames: a frame or two of a passing
#: lorry or a flash does not fill the log, a covered lens or a knocked camera is told within a second.
SETTLED_FRAMES = 5


class SceneWatch:
    """What one camera's frames say of its scene, for the health and the log: the settled scene fitness state, since
    when, and the view's registration (module docstring)."""

    def __init__(self, camera: str) -> None:
        self.camera = camera
        self.state: str | None = None  # the settled state (None before the first frame has settled one)
        self.reason = ""
        self.since: float | None = None  # monotonic time the settled state began
        self.view: tuple[tuple[int, int] | None, float | None] = (None, None)  # registered_px, registered_roll_deg
        self._candidate: tuple[str, tuple] | None = None
        self._held, self._first_seen = 0, 0.0

    def update(self, fitness: FrameFitness, now: float) -> None:
        """One frame's ``fitness`` at ``now`` (monotonic); logs a change once it has held :data:`SETTLED_FRAMES`."""
        view = (fitness.registered_px, fitness.registered_roll_deg)
        seen = (fitness.state, view)
        if seen == (self.state, self.view):
            self._candidate, self._held = None, 0
            self.reason = fitness.reason
            return
        if seen != self._candidate:
            self._candidate, self._held, self._first_seen = seen, 0, now
        self._held += 1
        if self._held < SETTLED_FRAMES and self.state is not None:
            return
        if fitness.state != self.state:
            level = logging.WARNING if fitness.state in UNFIT_STATES else logging.INFO
            log.log(level, "camera %s: scene %s%s", self.camera, fitness.state,
                    f" ({fitness.reason})" if fitness.reason else (" again" if self.state is not None else ""))
            self.since = self._first_seen
        if view != self.view:
            log.log(logging.INFO if view[0] is None else logging.WARNING, "camera %s: the view is %s", self.camera,
                    _view_words(*view))
        self.state, self.view, self.reason = fitness.state, view, fitness.reason
        self._candidate, self._held = None, 0

    def health(self, now: float) -> dict:
        shift, roll = self.view
        return {"state": self.state, "reason": self.reason or None,
                "for_s": None if self.since is None else round(now - self.since, 1),
                "registered_px": None if shift is None else list(shift), "registered_roll_deg": roll}


def _view_words(shift: tuple[int, int] | None, roll: float | None) -> str:
    if shift is None:
        return "the background's again"
    turned = f", turned {roll:+.2f} degrees" if roll else ""
    return f"moved ({shift[0]}, {shift[1]}) px{turned} from the background's, and compensated"


class EventSink:
    """Where every camera's events go: the queue (then the broker) and, when configured, JSON Lines files."""

    def __init__(self, config: ServeConfig, queue: EventQueue, metrics: ServiceMetrics) -> None:
        self.prefix, self.queue, self.metrics = config.mqtt.topic_prefix, queue, metrics
        self.publisher: Publisher | None = None
        self.lines: logging.Logger | None = None
        if config.events.jsonl is not None:
            config.events.jsonl.mkdir(parents=True, exist_ok=True)
            handler = logging.handlers.RotatingFileHandler(
                config.events.jsonl / "events.jsonl", maxBytes=config.events.jsonl_max_bytes,
                backupCount=config.events.jsonl_backups)
            handler.setFormatter(logging.Formatter("%(message)s"))
            self.lines = logging.getLogger(f"vc.serve.events.{id(self)}")
            self.lines.propagate = False
            self.lines.setLevel(logging.INFO)
            self.lines.addHandler(handler)

    def put(self, camera: str, events: list[dict]) -> None:
        for event in events:
            payload = json.dumps(event, separators=(",", ":"))
            dropped = self.queue.push(f"{self.prefix}/{camera}/events", payload)
            self.metrics.events_made.labels(camera, event["type"]).inc()
            self.metrics.events_dropped.inc(dropped)
            if self.lines is not None:
                self.lines.info(payload)
        if events and self.publisher is not None:
            self.publisher.notify()

    def close(self) -> None:
        if self.lines is not None:
            for handler in list(self.lines.handlers):
                handler.close()
                self.lines.removeHandler(handler)


class CameraWorker(threading.Thread):
    """One camera: its ``bundle`` (loaded, and checked against the camera's public key), its reader, tracker and
    events."""

    def __init__(self, camera: CameraSettings, bundle: Bundle, config: ServeConfig, sink: EventSink,
                 metrics: ServiceMetrics) -> None:
        super().__init__(name=f"run-{camera.name}", daemon=True)
        self.camera, self.sink, self.metrics = camera, sink, metrics
        self.stale_after_s = config.stale_after_s(camera)
        self.tracker = Tracker()
        self.runtime = Runtime(bundle, threads=camera.threads, unfit=camera.unfit, engine=camera.engine,
                               weak_people_above=self.tracker.config.weak_people_above)
        self.events = TrackEvents(camera.name, SceneZones(bundle.manifest["camera"], list(bundle.zones)),
                                  config.events.update_interval_s, self.tracker.config.coast_min_observations)
        self.reader = CameraReader(camera, bundle.frame_size, self._counted)
        self.started = time.monotonic()
        self.frames_run = 0
        self.scene = SceneWatch(camera.name)
        self.last_fault: str | None = None
        self._stopping = threading.Event()
        self._last_time = -float("inf")

    def _counted(self, kind: str) -> None:
        metric = {"frame": self.metrics.frames_read, "dropped": self.metrics.frames_dropped,
                  "refused": self.metrics.frames_refused, "reconnect": self.metrics.reconnects}[kind]
        metric.labels(self.camera.name).inc()

    def stop(self) -> None:
        self.reader.stop()
        self._stopping.set()

    def run(self) -> None:
        self.reader.start()
        try:
            while not self._stopping.is_set():
                frame = self.reader.latest.take(timeout_s=0.5)
                if frame is None:
                    self._expire(time.monotonic())
                    continue
                try:
                    self.process(frame)
                except Exception as error:  # a fault stays in its frame: logged, counted, reported; the camera goes on
                    self.last_fault = f"frame {frame.number}: {type(error).__name__}: {error}"
                    self.metrics.faults.labels(self.camera.name).inc()
                    log.error("camera %s: %s\n%s", self.camera.name, self.last_fault, traceback.format_exc())
            self.sink.put(self.camera.name, self.events.end_all(max(time.monotonic(), self._last_time), "shutdown"))
        finally:
            self.reader.stop()
            self.reader.join(timeout=10)
            self.runtime.close()

    def process(self, frame: CapturedFrame) -> None:
        """One frame: run, tracked, its events queued, counted; its scene fitness watched."""
        start = time.perf_counter()
        time_s = max(frame.monotonic, self._last_time + 1e-6)  # the tracker needs strictly increasing times
        self._last_time = time_s
        result = self.runtime.run(frame.image)
        people = result.reported(self.tracker.update(result.people, time_s, frame.image))
        live = {track.identity for track in self.tracker.tracks}
        events = self.events.update(people, live, time_s, frame.wall_time, frame.number)
        self.sink.put(self.camera.name, events)
        name = self.camera.name
        self.frames_run += 1
        self.metrics.frames_run.labels(name).inc()
        self.metrics.people.labels(name).inc(len(people))
        self.metrics.frames_by_fitness.labels(name, result.fitness.state).inc()
        self.scene.update(result.fitness, frame.monotonic)
        self.metrics.tracks.labels(name).inc(sum(event["type"] == "new" for event in events))
        if result.suppressed:
            self.metrics.frames_withheld.labels(name).inc()
        else:
            self.metrics.network_seconds.labels(name).observe(result.network_s)
            self.metrics.decode_seconds.labels(name).observe(result.decode_s)
        self.metrics.frame_seconds.labels(name).observe(time.perf_counter() - start)

    def _expire(self, now: float) -> None:
        """A silent camera's tracks end when the tracker would end them."""
        gap = self.tracker.config.max_gap_s
        live = {track.identity for track in self.tracker.tracks if now - track.times[-1] <= gap}
        if set(self.events.tracks) - live:
            self.sink.put(self.camera.name, self.events.update([], live, max(now, self._last_time), time.time(), 0))

    def health(self, now: float) -> dict:
        status = self.reader.snapshot()
        age = age_s(status.last_frame_monotonic, self.started, now)
        stale = status.state != "finished" and age > self.stale_after_s
        return {"state": status.state, "connected": status.state == "connected", "stale": stale,
                "last_frame_age_s": round(age, 3) if status.last_frame_monotonic is not None else None,
                "frames_per_second": round(frames_per_second(status.recent, now), 2),
                "frames_read": status.frames_read, "frames_run": self.frames_run,
                "frames_dropped": self.reader.latest.dropped, "frames_refused": status.frames_refused,
                "reconnects": status.reconnects, "live_tracks": len(self.events.tracks),
                "scene": self.scene.health(now), "last_error": status.last_error, "last_fault": self.last_fault}


class Service:
    """Every camera of ``config``, the queue, the publisher and the health server. :meth:`run` blocks until
    :meth:`stop`."""

    def __init__(self, config: ServeConfig) -> None:
        self.config = config
        use_stream_options(config.rtsp_transport)
        self.metrics = ServiceMetrics()
        # every bundle checked before anything is written: a bad one raises InputError naming it
        bundles = [load_bundle(camera.bundle, camera.public_key) for camera in config.cameras]
        self.queue = EventQueue(config.events.queue, config.events.queue_limit)
        self.sink = EventSink(config, self.queue, self.metrics)
        self.workers = [CameraWorker(camera, bundle, config, self.sink, self.metrics)
                        for camera, bundle in zip(config.cameras, bundles, strict=True)]
        self.publisher = Publisher(config.mqtt, self.queue, on_published=self.metrics.events_published.inc)
        self.sink.publisher = self.publisher
        self.http = HealthServer(config.http.host, config.http.port, self.health, self.metrics, self._refresh)
        self._stopping = threading.Event()

    @property
    def port(self) -> int:
        return self.http.port

    def health(self) -> tuple[bool, dict]:
        now = time.monotonic()
        cameras = {worker.camera.name: worker.health(now) for worker in self.workers}
        healthy = not any(camera["stale"] for camera in cameras.values())
        return healthy, {"healthy": healthy, "cameras": cameras,
                         "broker": {"connected": self.publisher.connected, "queue_depth": self.queue.depth,
                                    "in_flight": self.publisher.in_flight, "published": self.publisher.published,
                                    "dropped": self.queue.dropped}}

    def _refresh(self) -> None:
        now = time.monotonic()
        self.metrics.queue_depth.set(self.queue.depth)
        self.metrics.broker_connected.set(int(self.publisher.connected))
        for worker in self.workers:
            status = worker.reader.snapshot()
            self.metrics.connected.labels(worker.camera.name).set(int(status.state == "connected"))
            self.metrics.frame_age.labels(worker.camera.name).set(age_s(status.last_frame_monotonic, worker.started,
                                                                        now))

    def run(self) -> None:
        """Start everything and serve until :meth:`stop`; then shut down in order (module docstring)."""
        self.http.start()
        self.publisher.start()
        for worker in self.workers:
            worker.start()
        log.info("vc-serve: %d camera(s); health and metrics on port %d", len(self.workers), self.port)
        self._stopping.wait()
        for worker in self.workers:
            worker.stop()
        for worker in self.workers:
            worker.join(timeout=30)
        self.publisher.stop(DRAIN_S)
        log.info("vc-serve: stopped; %d event(s) wait in %s", self.queue.depth, self.queue.path)
        self.queue.close()
        self.sink.close()
        self.http.stop()

    def stop(self) -> None:
        self._stopping.set()
