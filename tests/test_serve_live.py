"""vc-serve against real servers, started here: GStreamer's RTSP server (tests/serve_rtsp_server.py) as the camera,
mosquitto as the broker, a paho-mqtt subscriber, and ``vc-serve`` itself as a process, as an appliance runs it.

The bundle sees the white squares the tests draw (tests/serve_factory.py), so each test chooses its people. The
faults are the ones a camera meets: the camera server killed and restarted, a stream that stalls, garbage on the
RTSP port, a resolution change, the broker killed for 20 s, SIGTERM during a burst of events.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import threading
import time
from pathlib import Path

import cv2
import pytest
from serve_factory import marker_bundle, marker_frame
from serve_servers import Broker, RtspCamera, Service, Subscriber, free_port, needs_broker, needs_rtsp, wait

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("serve_live")]

FRAME_SIZE = (128, 64)  # the test bundle's camera


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


def _serving(frames: Path, marker: Path, broker: Broker, tmp_path: Path, cleanup: list) -> tuple[RtspCamera, Service]:
    """``frames`` streamed by an RTSP camera at 10 frames/s and served by vc-serve, once its first 10 frames ran."""
    camera = RtspCamera(frames, fps=10)
    camera.start()
    cleanup.append(camera)
    service = Service(tmp_path, marker, camera.url, broker.port)
    service.start()
    cleanup.append(service)
    wait(lambda: service.camera()["frames_run"] >= 10, 20, "frames run")
    return camera, service


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
    health = wait(lambda: (lambda c: c if c["reconnects"] >= 1 else None)(service.camera()), 30,
                   "the stream's end")
    assert health["last_fault"] is None and health["frames_run"] >= 45
    assert service.terminate() == 0
    made = service.events()
    wait(lambda: len(subscriber.received()) == len(made), 10, "every event at the subscriber")
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
    camera, service = _serving(_frames(tmp_path / "frames", 300, _walkers), marker, broker, tmp_path, cleanup)
    camera.kill()
    gap = wait(lambda: (lambda c: c if c["state"] == "disconnected" else None)(service.camera()), 10,
                "the camera reported disconnected")
    assert gap["last_error"] and not gap["connected"]
    stale = wait(lambda: (lambda h: h if h["status"] == 503 else None)(service.health()), 10, "stale")
    assert stale["cameras"]["cam1"]["stale"] and not stale["healthy"]
    before = service.camera()["frames_read"]
    camera.start()
    back = wait(lambda: (lambda c: c if c["frames_read"] > before + 10 else None)(service.camera()), 30,
                 "frames again after the restart")
    assert back["reconnects"] >= 1 and back["connected"] and service.health()["status"] == 200
    assert service.process.poll() is None and "vc_camera_reconnects_total" in service.metrics()
    assert service.terminate() == 0


@needs_broker
@needs_rtsp
def test_a_stalled_stream_is_stale_within_twice_the_read_timeout(marker, broker, tmp_path, cleanup):
    # the service's read timeout is 1 s: stale after 2 s
    camera, service = _serving(_frames(tmp_path / "frames", 300, _walkers), marker, broker, tmp_path, cleanup)
    camera.process.send_signal(signal.SIGSTOP)  # the connection stays open; nothing comes through it
    stalled = time.monotonic()
    try:
        wait(lambda: service.health()["status"] == 503, 2 * 1 + 1.5, "503 from /healthz")
        assert time.monotonic() - stalled >= 1.5  # not before the frames stopped being fresh
    finally:
        camera.process.send_signal(signal.SIGCONT)
    wait(lambda: service.health()["status"] == 200, 30, "healthy again once the stream resumes")
    assert service.terminate() == 0


@needs_broker
def test_garbage_on_the_rtsp_port_is_a_camera_that_does_not_open_and_never_a_crash(marker, broker, tmp_path,
                                                                                   cleanup):
    port = free_port()
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
        retried = wait(lambda: (lambda c: c if c["reconnects"] >= 2 else None)(service.camera()), 30,
                        "the camera retried twice")
        assert retried["frames_read"] == 0 and retried["state"] in ("disconnected", "connecting")
        assert "cannot open" in retried["last_error"]
        wait(lambda: service.health()["status"] == 503, 10, "stale: no frame since the start")
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
    camera, service = _serving(right, marker, broker, tmp_path, cleanup)
    camera.kill()
    camera.folder = wrong
    camera.start()
    refused = wait(lambda: (lambda c: c if c["frames_refused"] >= 5 else None)(service.camera()), 30,
                    "frames of the new size refused")
    assert refused["last_error"] == "frames of 160x96, the bundle's camera is 128x64: not run"
    run_before = refused["frames_run"]
    time.sleep(1.0)
    assert service.camera()["frames_run"] <= run_before + 1  # none of them run (one may have been in flight)
    camera.kill()
    camera.folder = right
    camera.start()
    wait(lambda: service.camera()["frames_run"] >= run_before + 10, 30, "frames of the right size run again")
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
    wait(lambda: len(subscriber.received()) >= 10, 20, "events at the subscriber")
    broker.stop()
    down = time.monotonic()
    queued = wait(lambda: (lambda h: h if h["broker"]["queue_depth"] >= 20 else None)(service.health()), 20,
                   "events queued while the broker is down")
    assert not queued["broker"]["connected"]
    time.sleep(max(0.0, 20 - (time.monotonic() - down)))
    assert service.health()["broker"]["queue_depth"] > queued["broker"]["queue_depth"]
    broker.start()
    wait(lambda: service.health()["broker"]["queue_depth"] == 0, 30, "the queue delivered")
    assert service.terminate() == 0
    made = service.events()
    wait(lambda: {e["id"] for e in subscriber.received()} >= {e["id"] for e in made}, 20,
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
    wait(lambda: service.health()["broker"]["queue_depth"] >= 12, 20, "the burst under way")
    assert service.terminate() == 0  # mid-burst: SIGTERM finishes the frame in flight and ends the tracks
    made = service.events()
    assert [e["type"] for e in made].count("new") == 6 and made[-1]["type"] == "end"
    assert "event(s) kept in" in service.output()
    broker.start()
    quiet = _frames(tmp_path / "quiet", 1, lambda k: [])
    restarted = Service(tmp_path, marker, str(quiet), broker.port, camera={"fps": 10})
    restarted.start()
    cleanup.append(restarted)
    wait(lambda: len(subscriber.received()) >= len(made), 30, "the queue delivered after the restart")
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
        health = wait(lambda: (lambda c: c if c["frames_run"] >= 30 else None)(service.camera()), 20,
                       "frames run from the MJPEG stream")
        assert health["frames_refused"] == 0 and health["last_fault"] is None
        wait(lambda: {"new", "update"} <= {e["type"] for e in subscriber.received()}, 10, "events published")
    finally:
        camera.close()
    assert service.terminate() == 0
    subscriber.close()
    # both walkers announced (on a loaded machine frames are dropped, and a walker's track may break in two)
    assert len({e["track"] for e in service.events() if e["type"] == "new"}) >= 2
