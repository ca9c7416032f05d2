"""vc-serve against real servers, started here: GStreamer's RTSP server (tests/serve_rtsp_server.py) as the camera,
mosquitto as the broker, a paho-mqtt subscriber, and ``vc-serve`` itself as a process, as an appliance runs it.

The bundle sees the white squares the tests draw (tests/serve_factory.py), so each test chooses its people. The
faults are the ones a camera meets: the camera server killed and restarted, a stream that stalls, garbage on the
RTSP port, a resolution change, the broker killed for 20 s, SIGTERM during a burst of events.
"""

from __future__ import annotations

import getpass
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path

import cv2
import paho.mqtt.client as paho
import pytest
from serve_factory import marker_bundle, marker_frame

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("serve_live")]

HERE = Path(__file__).parent
MOSQUITTO = shutil.which("mosquitto") or ("/usr/sbin/mosquitto" if Path("/usr/sbin/mosquitto").exists() else None)
SYSTEM_PYTHON = "/usr/bin/python3"
VC_SERVE = Path(sys.executable).parent / "vc-serve"
FRAME_SIZE = (128, 64)  # the test bundle's camera


def _gst_rtsp_available() -> bool:
    if not Path(SYSTEM_PYTHON).exists():
        return False
    probe = ("import gi; gi.require_version('GstRtspServer', '1.0'); from gi.repository import GstRtspServer, Gst; "
             "Gst.init(None); assert Gst.ElementFactory.find('imagesequencesrc')")
    return subprocess.run([SYSTEM_PYTHON, "-c", probe], capture_output=True).returncode == 0


needs_broker = pytest.mark.skipif(MOSQUITTO is None, reason="mosquitto is not installed (make install installs it)")
needs_rtsp = pytest.mark.skipif(not _gst_rtsp_available(), reason="GStreamer's RTSP server and its Python bindings "
                                "are not installed (make install installs them)")


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _wait(condition, timeout_s: float, what: str, step_s: float = 0.1):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(step_s)
    raise AssertionError(f"timed out after {timeout_s} s waiting for {what}")


class Broker:
    """mosquitto on a free port, its sessions persisted across a restart (a subscriber's queued messages too)."""

    def __init__(self, folder: Path) -> None:
        self.port, self.folder, self.process = _free_port(), folder, None
        folder.mkdir(parents=True, exist_ok=True)
        # started by root, mosquitto would run as its own user, who cannot write the persistence file here
        (folder / "mosquitto.conf").write_text(
            f"listener {self.port} 127.0.0.1\nallow_anonymous true\npersistence true\n"
            f"persistence_location {folder}/\nmax_queued_messages 100000\nuser {getpass.getuser()}\n")

    def start(self) -> None:
        self.process = subprocess.Popen([MOSQUITTO, "-c", str(self.folder / "mosquitto.conf")],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _wait(lambda: _listening(self.port), 10, "mosquitto to listen")

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()  # mosquitto writes its persistence file as it exits
            self.process.wait(10)


def _listening(port: int) -> bool:
    with socket.socket() as probe:
        return probe.connect_ex(("127.0.0.1", port)) == 0


class Subscriber:
    """A paho-mqtt subscriber to every camera's events, with a session that survives its broker's restart."""

    def __init__(self, port: int) -> None:
        self.messages: list[dict] = []
        self.lock = threading.Lock()
        self.client = paho.Client(paho.CallbackAPIVersion.VERSION2, client_id=f"test-subscriber-{port}",
                                  clean_session=False)
        self.subscribed = threading.Event()
        self.client.on_connect = lambda client, *_: client.subscribe("vc/+/events", qos=1)
        self.client.on_subscribe = lambda *_: self.subscribed.set()
        self.client.on_message = self._received
        self.client.reconnect_delay_set(0.2, 1)
        self.client.connect("127.0.0.1", port, keepalive=5)
        self.client.loop_start()
        assert self.subscribed.wait(10), "the subscriber did not subscribe"

    def _received(self, client, userdata, message) -> None:
        with self.lock:
            self.messages.append({"topic": message.topic, "dup": message.dup, **json.loads(message.payload)})

    def received(self) -> list[dict]:
        with self.lock:
            return list(self.messages)

    def close(self) -> None:
        self.client.disconnect()
        self.client.loop_stop()


class RtspCamera:
    """GStreamer's RTSP server streaming ``folder`` at ``fps`` on a port of its own (kept across restarts)."""

    def __init__(self, folder: Path, fps: int, port: int | None = None) -> None:
        self.folder, self.fps, self.port, self.process = folder, fps, port or _free_port(), None

    @property
    def url(self) -> str:
        return f"rtsp://127.0.0.1:{self.port}/cam"

    def start(self) -> None:
        self.process = subprocess.Popen([SYSTEM_PYTHON, str(HERE / "serve_rtsp_server.py"), str(self.port),
                                         str(self.folder), str(self.fps)], stdout=subprocess.PIPE,
                                        stderr=subprocess.DEVNULL, text=True)
        assert self.process.stdout.readline().strip() == "ready"

    def kill(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait(10)


class Service:
    """``vc-serve CONFIG`` as a process; its health and its events' JSON Lines copy."""

    def __init__(self, folder: Path, bundle: Path, source: str, broker_port: int, **settings) -> None:
        self.folder, self.http_port = folder, _free_port()
        camera = {"name": "cam1", "bundle": str(bundle), "source": source,
                  "reading": {"open_timeout_s": 2, "read_timeout_s": 1, "backoff_initial_s": 0.2,
                              "backoff_max_s": 1}, **settings.pop("camera", {})}
        config = {"cameras": [camera], "mqtt": {"host": "127.0.0.1", "port": broker_port},
                  "events": {"queue": "queue.sqlite", "jsonl": "events", **settings.pop("events", {})},
                  "http": {"host": "127.0.0.1", "port": self.http_port}}
        self.config = folder / "serve.yaml"
        self.config.write_text(json.dumps(config))  # JSON is YAML
        self.process = None

    def start(self) -> None:
        self.log = open(self.folder / "serve.log", "a")
        self.process = subprocess.Popen([str(VC_SERVE), str(self.config)], stdout=self.log, stderr=subprocess.STDOUT)
        _wait(lambda: self.health() is not None, 30, "vc-serve's health page")

    def health(self) -> dict | None:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{self.http_port}/healthz", timeout=2) as answer:
                return {"status": answer.status, **json.loads(answer.read())}
        except urllib.error.HTTPError as error:
            return {"status": error.code, **json.loads(error.read())}
        except (urllib.error.URLError, ConnectionError, TimeoutError):
            return None

    def camera(self) -> dict:
        return self.health()["cameras"]["cam1"]

    def metrics(self) -> str:
        with urllib.request.urlopen(f"http://127.0.0.1:{self.http_port}/metrics", timeout=2) as answer:
            return answer.read().decode()

    def terminate(self) -> int:
        self.process.send_signal(signal.SIGTERM)
        code = self.process.wait(30)
        self.log.close()
        return code

    def events(self) -> list[dict]:
        """Every event made, in order (the JSON Lines copy, rotated files included)."""
        lines = []
        for path in sorted((self.folder / "events").glob("events.jsonl*"), reverse=True):
            lines += path.read_text().splitlines()
        return [json.loads(line) for line in lines]

    def output(self) -> str:
        return (self.folder / "serve.log").read_text()


@pytest.fixture
def marker(bundle, tmp_path) -> Path:
    return marker_bundle(bundle, tmp_path / "markers")


@pytest.fixture
def broker(tmp_path):
    server = Broker(tmp_path / "broker")
    server.start()
    yield server
    server.stop()


@pytest.fixture
def cleanup():
    """Processes to kill whatever a test's outcome."""
    started: list = []
    yield started
    for thing in started:
        process = getattr(thing, "process", None)
        if process is not None and process.poll() is None:
            process.kill()
            process.wait(10)


def _frames(folder: Path, count: int, people, size=FRAME_SIZE) -> Path:
    """``count`` JPEG frames; ``people(k)`` lists the marked cells of frame k (0-based)."""
    folder.mkdir(parents=True, exist_ok=True)
    for k in range(count):
        image = marker_frame(size, people(k))
        cv2.imwrite(str(folder / f"{k + 1:05d}.jpg"), image, [cv2.IMWRITE_JPEG_QUALITY, 95])
    return folder


def _walkers(k: int) -> list[tuple[int, int]]:
    """One person walking right along row 8, a second standing at (20, 5) for frames 5-29."""
    return [(2 + k // 3, 8)] + ([(20, 5)] if 5 <= k < 30 else [])


@needs_broker
@needs_rtsp
def test_served_from_rtsp_the_people_are_the_ones_vc_run_finds_in_the_same_frames(marker, broker, tmp_path, cleanup):
    # The server starts its stream as the client asks for it and sends what it made meanwhile at once: the service
    # keeps the latest of those, so the stream opens on 10 empty frames; the people come after.
    frames = _frames(tmp_path / "frames", 50, lambda k: _walkers(k - 10) if k >= 10 else [])
    camera = RtspCamera(frames, fps=10)
    camera.start()
    cleanup.append(camera)
    subscriber = Subscriber(broker.port)
    service = Service(tmp_path, marker, camera.url, broker.port, events={"update_interval_s": 0})
    service.start()
    cleanup.append(service)
    # at its end the stream is opened again and sent from its start: frames 51, 52, ... are its first again
    health = _wait(lambda: (lambda c: c if c["reconnects"] >= 1 else None)(service.camera()), 30,
                   "the stream's end")
    assert health["last_fault"] is None and health["frames_run"] >= 45
    assert service.terminate() == 0
    made = service.events()
    _wait(lambda: len(subscriber.received()) == len(made), 10, "every event at the subscriber")
    subscriber.close()

    from vc.cli.run import main as vc_run
    assert vc_run([str(marker), str(frames), "-o", str(tmp_path / "run"), "--fps", "10", "--quiet"]) == 0
    expected, announced, seen = {}, {}, {}
    for line in (tmp_path / "run" / "detections.jsonl").read_text().splitlines():
        frame = json.loads(line)
        people = [p for p in frame["people"] if not p["coasted"]]
        expected[frame["frame"]] = [p["box"] for p in people]
        for person in people:  # a track is announced once seen three times: from then on it is served
            seen[person["track"]] = seen.get(person["track"], 0) + 1
        announced[frame["frame"]] = sum(seen[p["track"]] >= 3 for p in people)
    served = [event for event in made if event["type"] != "end" and not event["carried"] and event["frame"] <= 50]
    assert len(served) >= 50  # two people over most of the 40 frames with people
    for event in served:  # every person served is one vc-run finds in that frame (boxes to the JPEG's rounding)
        assert any(max(abs(a - b) for a, b in zip(box, event["box"], strict=True)) < 0.5
                   for box in expected[event["frame"]]), event
    # frame by frame (no frame with people was dropped), to the stream's last frame but one: a stream's last frame
    # can be lost in its end
    per_frame = {frame: sum(event["frame"] == frame for event in served) for frame in expected if frame < 50}
    assert per_frame == {frame: count for frame, count in announced.items() if frame < 50}
    assert [e["id"] for e in subscriber.received()] == [e["id"] for e in made]
    assert {e["type"] for e in made} == {"new", "update", "end"} and all(e["ground_m"] for e in made)


@needs_broker
@needs_rtsp
def test_a_camera_server_killed_and_restarted_is_reconnected_and_the_gap_reported(marker, broker, tmp_path, cleanup):
    frames = _frames(tmp_path / "frames", 300, _walkers)
    camera = RtspCamera(frames, fps=10)
    camera.start()
    cleanup.append(camera)
    service = Service(tmp_path, marker, camera.url, broker.port)
    service.start()
    cleanup.append(service)
    _wait(lambda: service.camera()["frames_run"] >= 10, 20, "frames run")
    camera.kill()
    gap = _wait(lambda: (lambda c: c if c["state"] == "disconnected" else None)(service.camera()), 10,
                "the camera reported disconnected")
    assert gap["last_error"] and not gap["connected"]
    stale = _wait(lambda: (lambda h: h if h["status"] == 503 else None)(service.health()), 10, "stale")
    assert stale["cameras"]["cam1"]["stale"] and not stale["healthy"]
    before = service.camera()["frames_read"]
    camera.start()
    back = _wait(lambda: (lambda c: c if c["frames_read"] > before + 10 else None)(service.camera()), 30,
                 "frames again after the restart")
    assert back["reconnects"] >= 1 and back["connected"] and service.health()["status"] == 200
    assert service.process.poll() is None and "vc_camera_reconnects_total" in service.metrics()
    assert service.terminate() == 0


@needs_broker
@needs_rtsp
def test_a_stalled_stream_is_stale_within_twice_the_read_timeout(marker, broker, tmp_path, cleanup):
    frames = _frames(tmp_path / "frames", 300, _walkers)
    camera = RtspCamera(frames, fps=10)
    camera.start()
    cleanup.append(camera)
    service = Service(tmp_path, marker, camera.url, broker.port)  # read timeout 1 s: stale after 2 s
    service.start()
    cleanup.append(service)
    _wait(lambda: service.camera()["frames_run"] >= 10, 20, "frames run")
    camera.process.send_signal(signal.SIGSTOP)  # the connection stays open; nothing comes through it
    stalled = time.monotonic()
    try:
        _wait(lambda: service.health()["status"] == 503, 2 * 1 + 1.5, "503 from /healthz")
        assert time.monotonic() - stalled >= 1.5  # not before the frames stopped being fresh
    finally:
        camera.process.send_signal(signal.SIGCONT)
    _wait(lambda: service.health()["status"] == 200, 30, "healthy again once the stream resumes")
    assert service.terminate() == 0


@needs_broker
def test_garbage_on_the_rtsp_port_is_a_camera_that_does_not_open_and_never_a_crash(marker, broker, tmp_path,
                                                                                   cleanup):
    port = _free_port()
    listener = socket.socket()
    listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    listener.bind(("127.0.0.1", port))
    listener.listen()
    listener.settimeout(0.2)
    stop = threading.Event()

    def garbage() -> None:
        noise = os.urandom(4096)
        while not stop.is_set():
            try:
                connection, _ = listener.accept()
            except TimeoutError:
                continue
            with connection:
                try:
                    connection.sendall(b"RTSP/1.0 200 OK\r\nCSeq: 1\r\n\r\n" + noise)
                    connection.recv(4096)
                except OSError:
                    pass

    thread = threading.Thread(target=garbage, daemon=True)
    thread.start()
    service = Service(tmp_path, marker, f"rtsp://127.0.0.1:{port}/cam", broker.port)
    service.start()
    cleanup.append(service)
    try:
        retried = _wait(lambda: (lambda c: c if c["reconnects"] >= 2 else None)(service.camera()), 30,
                        "the camera retried twice")
        assert retried["frames_read"] == 0 and retried["state"] in ("disconnected", "connecting")
        assert "cannot open" in retried["last_error"]
        _wait(lambda: service.health()["status"] == 503, 10, "stale: no frame since the start")
        assert service.process.poll() is None
    finally:
        stop.set()
        thread.join()
        listener.close()
    assert service.terminate() == 0


@needs_broker
@needs_rtsp
def test_frames_of_another_size_are_refused_by_name_and_the_right_size_runs_again(marker, broker, tmp_path,
                                                                                  cleanup):
    right = _frames(tmp_path / "right", 300, _walkers)
    wrong = _frames(tmp_path / "wrong", 300, lambda k: [(2, 4)], size=(160, 96))
    camera = RtspCamera(right, fps=10)
    camera.start()
    cleanup.append(camera)
    service = Service(tmp_path, marker, camera.url, broker.port)
    service.start()
    cleanup.append(service)
    _wait(lambda: service.camera()["frames_run"] >= 5, 20, "frames run")
    camera.kill()
    camera.folder = wrong
    camera.start()
    refused = _wait(lambda: (lambda c: c if c["frames_refused"] >= 5 else None)(service.camera()), 30,
                    "frames of the new size refused")
    assert refused["last_error"] == "frames of 160x96, the bundle's camera is 128x64: not run"
    run_before = refused["frames_run"]
    time.sleep(1.0)
    assert service.camera()["frames_run"] <= run_before + 1  # none of them run (one may have been in flight)
    camera.kill()
    camera.folder = right
    camera.start()
    _wait(lambda: service.camera()["frames_run"] >= run_before + 10, 30, "frames of the right size run again")
    assert service.terminate() == 0
    assert service.output().count("frames of 160x96") == 1  # logged once per change of size, not per frame


def _crowd(k: int) -> list[tuple[int, int]]:
    """Six people appearing together for frames 3-14, then gone: a burst of events."""
    return [(2 + 3 * n, 5 + (n % 2) * 4) for n in range(6)] if 3 <= k < 15 else []


@needs_broker
def test_events_made_while_the_broker_is_down_for_20_s_all_arrive_after_in_order_once(marker, broker, tmp_path,
                                                                                     cleanup):
    frames = _frames(tmp_path / "frames", 20, _crowd)
    subscriber = Subscriber(broker.port)
    service = Service(tmp_path, marker, str(frames), broker.port,
                      camera={"fps": 10, "loop": True}, events={"update_interval_s": 0.3})
    service.start()
    cleanup.append(service)
    _wait(lambda: len(subscriber.received()) >= 10, 20, "events at the subscriber")
    broker.stop()
    down = time.monotonic()
    queued = _wait(lambda: (lambda h: h if h["broker"]["queue_depth"] >= 20 else None)(service.health()), 20,
                   "events queued while the broker is down")
    assert not queued["broker"]["connected"]
    time.sleep(max(0.0, 20 - (time.monotonic() - down)))
    assert service.health()["broker"]["queue_depth"] > queued["broker"]["queue_depth"]
    broker.start()
    _wait(lambda: service.health()["broker"]["queue_depth"] == 0, 30, "the queue delivered")
    assert service.terminate() == 0
    made = service.events()
    _wait(lambda: {e["id"] for e in subscriber.received()} >= {e["id"] for e in made}, 20,
          "every event at the subscriber")
    time.sleep(0.5)
    received = subscriber.received()
    subscriber.close()
    # The broker itself sends again, flagged DUP, what it had sent the subscriber unacknowledged when it went down
    # (its QoS 1 to the subscriber): the subscriber knows them by their ids. Anything else twice would be the
    # service's.
    first_time = [e for k, e in enumerate(received) if not (e["dup"] and e["id"] in {r["id"] for r in received[:k]})]
    assert [e["id"] for e in first_time] == [e["id"] for e in made]  # all, once each, in the order made


@needs_broker
def test_sigterm_during_a_burst_keeps_every_event_for_the_restart(marker, broker, tmp_path, cleanup):
    frames = _frames(tmp_path / "frames", 20, _crowd)
    subscriber = Subscriber(broker.port)
    broker.stop()  # the burst is queued on disk, not yet delivered
    service = Service(tmp_path, marker, str(frames), broker.port, camera={"fps": 10},
                      events={"update_interval_s": 0})
    service.start()
    cleanup.append(service)
    _wait(lambda: service.health()["broker"]["queue_depth"] >= 12, 20, "the burst under way")
    assert service.terminate() == 0  # mid-burst: SIGTERM finishes the frame in flight and ends the tracks
    made = service.events()
    assert [e["type"] for e in made].count("new") == 6 and made[-1]["type"] == "end"
    assert "event(s) kept in" in service.output()
    broker.start()
    quiet = _frames(tmp_path / "quiet", 1, lambda k: [])
    restarted = Service(tmp_path, marker, str(quiet), broker.port, camera={"fps": 10})
    restarted.start()
    cleanup.append(restarted)
    _wait(lambda: len(subscriber.received()) >= len(made), 30, "the queue delivered after the restart")
    assert restarted.terminate() == 0
    received = subscriber.received()
    subscriber.close()
    assert [e["id"] for e in received] == [e["id"] for e in made]


class MjpegCamera:
    """An HTTP MJPEG camera (multipart/x-mixed-replace, as many IP cameras serve it) streaming ``frames`` at
    ``fps`` to each client, in a thread of this process."""

    def __init__(self, frames: Path, fps: int) -> None:
        from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

        images = [path.read_bytes() for path in sorted(frames.glob("*.jpg"))]

        class Handler(BaseHTTPRequestHandler):
            def do_GET(self) -> None:  # noqa: N802 (the standard library's name)
                self.send_response(200)
                self.send_header("Content-Type", "multipart/x-mixed-replace; boundary=frame")
                self.end_headers()
                try:
                    for image in images:
                        self.wfile.write(b"--frame\r\nContent-Type: image/jpeg\r\nContent-Length: %d\r\n\r\n"
                                         % len(image) + image + b"\r\n")
                        time.sleep(1 / fps)
                except (BrokenPipeError, ConnectionResetError):
                    pass

            def log_message(self, *args) -> None:
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.server.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.server.server_address[1]}/video.mjpg"
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


@needs_broker
def test_an_http_mjpeg_camera_is_read_and_its_people_published(marker, broker, tmp_path, cleanup):
    camera = MjpegCamera(_frames(tmp_path / "frames", 40, _walkers), fps=10)
    subscriber = Subscriber(broker.port)
    service = Service(tmp_path, marker, camera.url, broker.port)
    service.start()
    cleanup.append(service)
    try:
        health = _wait(lambda: (lambda c: c if c["frames_run"] >= 30 else None)(service.camera()), 20,
                       "frames run from the MJPEG stream")
        assert health["frames_refused"] == 0 and health["last_fault"] is None
        _wait(lambda: {"new", "update"} <= {e["type"] for e in subscriber.received()}, 10, "events published")
    finally:
        camera.close()
    assert service.terminate() == 0
    subscriber.close()
    assert {e["track"] for e in service.events() if e["type"] == "new"} == {1, 2}
