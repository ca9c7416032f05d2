"""What a monitoring system reads: ``/healthz`` (JSON, 503 when a camera is stale) and ``/metrics`` (Prometheus
text format, prometheus-client's own registry and exposition).

The metrics are counters and histograms per camera (label ``camera``) and for the event queue; the health is the
state of each camera's reader now. A camera is **stale** when its last frame is older than the configuration's
``stale_after_s`` (default: twice its read timeout, within which a stalled stream is closed and retried), or when it
never delivered a frame that long after starting; a file played once that has ended is ``finished``, not stale.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

from prometheus_client import CONTENT_TYPE_LATEST, CollectorRegistry, Counter, Gauge, Histogram, generate_latest

log = logging.getLogger("vc.serve")

#: Seconds: a PETS09 frame runs in ~10-30 ms on two cores; a slow appliance in 100s of ms.
TIME_BUCKETS = (0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0)


class ServiceMetrics:
    """Every metric ``vc-serve`` exports, in one registry of its own."""

    def __init__(self) -> None:
        self.registry = registry = CollectorRegistry()

        def counter(name: str, text: str, labels=("camera",)) -> Counter:
            return Counter(name, text, labels, registry=registry)

        self.frames_read = counter("vc_frames_read", "Frames read from the camera")
        self.frames_run = counter("vc_frames_run", "Frames the networks ran on")
        self.frames_dropped = counter("vc_frames_dropped", "Frames replaced by a newer one before they were run")
        self.frames_refused = counter("vc_frames_refused", "Frames of another size than the bundle's camera")
        self.frames_withheld = counter("vc_frames_withheld", "Frames whose people were withheld by the scene fitness")
        self.frames_by_fitness = counter("vc_frames_fitness", "Frames run, by their scene fitness state",
                                         ("camera", "state"))
        self.reconnects = counter("vc_camera_reconnects", "Times a camera was reopened")
        self.faults = counter("vc_frame_faults", "Frames whose processing failed (logged; the service went on)")
        self.people = counter("vc_people", "People reported (one per person per frame)")
        self.tracks = counter("vc_tracks", "Tracks announced (new events)")
        self.events_made = counter("vc_events_made", "Events made", ("camera", "type"))
        self.events_published = Counter("vc_events_published", "Events the broker acknowledged", registry=registry)
        self.events_dropped = Counter("vc_events_dropped", "Events dropped from a full queue", registry=registry)
        self.queue_depth = Gauge("vc_event_queue_depth", "Events waiting for the broker", registry=registry)
        self.broker_connected = Gauge("vc_broker_connected", "1 while connected to the broker", registry=registry)
        self.network_seconds = Histogram("vc_network_seconds", "The networks' time per frame (regions summed)",
                                         ("camera",), buckets=TIME_BUCKETS, registry=registry)
        self.decode_seconds = Histogram("vc_decode_seconds", "Decoding heat maps into people per frame",
                                        ("camera",), buckets=TIME_BUCKETS, registry=registry)
        self.frame_seconds = Histogram("vc_frame_seconds", "A frame from taken to its events queued (fitness, "
                                       "networks, decoding, tracking)", ("camera",), buckets=TIME_BUCKETS,
                                       registry=registry)
        self.connected = Gauge("vc_camera_connected", "1 while the camera is delivering", ("camera",),
                               registry=registry)
        self.frame_age = Gauge("vc_camera_frame_age_seconds", "Seconds since the camera's last frame", ("camera",),
                               registry=registry)

    def exposition(self) -> bytes:
        return generate_latest(self.registry)


class HealthServer:
    """``/healthz`` and ``/metrics`` on ``host:port`` (port 0: any free one, :attr:`port` says which), served from
    a thread. ``health()`` returns (healthy, report); ``refresh()`` updates the gauges before a scrape."""

    def __init__(self, host: str, port: int, health: Callable[[], tuple[bool, dict]],
                 metrics: ServiceMetrics, refresh: Callable[[], None]) -> None:
        outer = self

        class Handler(BaseHTTPRequestHandler):
            def do_GET(self) -> None:  # noqa: N802 (the standard library's name)
                path = self.path.split("?")[0]
                if path == "/healthz":
                    healthy, report = outer.health()
                    self._answer(200 if healthy else 503, "application/json",
                                 (json.dumps(report, indent=1) + "\n").encode())
                elif path == "/metrics":
                    outer.refresh()
                    self._answer(200, CONTENT_TYPE_LATEST, outer.metrics.exposition())
                else:
                    self._answer(404, "text/plain", b"vc-serve: /healthz or /metrics\n")

            def _answer(self, status: int, kind: str, body: bytes) -> None:
                self.send_response(status)
                self.send_header("Content-Type", kind)
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, format: str, *args) -> None:  # noqa: A002 (the standard library's name)
                log.debug("http: " + format, *args)

        self.health, self.metrics, self.refresh = health, metrics, refresh
        self.server = ThreadingHTTPServer((host, port), Handler)
        self.server.daemon_threads = True
        self.port = self.server.server_address[1]
        self._thread = threading.Thread(target=self.server.serve_forever, name="http", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self.server.shutdown()
        self.server.server_close()


def frames_per_second(recent: list[float], now: float, window_s: float = 5.0) -> float:
    """The rate of the frame times ``recent`` (monotonic seconds) over the last ``window_s``."""
    inside = [t for t in recent if t > now - window_s]
    if len(inside) < 2:
        return 0.0
    return (len(inside) - 1) / max(inside[-1] - inside[0], 1e-6)


def age_s(last: float | None, since: float, now: float | None = None) -> float:
    """Seconds since ``last`` (monotonic), or since ``since`` when there was none."""
    now = time.monotonic() if now is None else now
    return now - (last if last is not None else since)
