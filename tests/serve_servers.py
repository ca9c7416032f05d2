"""Real servers for vc-serve's tests, each started by the test that needs it: mosquitto as the broker, GStreamer's RTSP
server as a camera (tests/serve_rtsp_server.py), a paho-mqtt subscriber, and ``vc-serve`` itself as a process."""

from __future__ import annotations

import getpass
import json
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

import paho.mqtt.client as paho
import pytest

HERE = Path(__file__).parent
MOSQUITTO = shutil.which("mosquitto") or ("/usr/sbin/mosquitto" if Path("/usr/sbin/mosquitto").exists() else None)
SYSTEM_PYTHON = "/usr/bin/python3"
VC_SERVE = Path(sys.executable).parent / "vc-serve"


def _gst_rtsp_available() -> bool:
    if not Path(SYSTEM_PYTHON).exists():
        return False
    probe = ("import gi; gi.require_version('GstRtspServer', '1.0'); from gi.repository import GstRtspServer, Gst; "
             "Gst.init(None); assert Gst.ElementFactory.find('imagesequencesrc')")
    return subprocess.run([SYSTEM_PYTHON, "-c", probe], capture_output=True).returncode == 0


needs_broker = pytest.mark.skipif(MOSQUITTO is None, reason="mosquitto is not installed (make install installs it)")
needs_rtsp = pytest.mark.skipif(not _gst_rtsp_available(), reason="GStreamer's RTSP server and its Python bindings "
                                "are not installed (make install installs them)")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait(condition, timeout_s: float, what: str, step_s: float = 0.1):
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
        self.port, self.folder, self.process = free_port(), folder, None
        folder.mkdir(parents=True, exist_ok=True)
        # started by root, mosquitto would run as its own user, who cannot write the persistence file here
        (folder / "mosquitto.conf").write_text(
            f"listener {self.port} 127.0.0.1\nallow_anonymous true\npersistence true\n"
            f"persistence_location {folder}/\nmax_queued_messages 100000\nuser {getpass.getuser()}\n")

    def start(self) -> None:
        self.process = subprocess.Popen([MOSQUITTO, "-c", str(self.folder / "mosquitto.conf")],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wait(lambda: _listening(self.port), 10, "mosquitto to listen")

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
        self.folder, self.fps, self.port, self.process = folder, fps, port or free_port(), None

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
    """``vc-serve CONFIG`` (``executable``) as a process; its health and its events' JSON Lines copy."""

    def __init__(self, folder: Path, bundle: Path, source: str, broker_port: int, executable: Path = VC_SERVE,
                 **settings) -> None:
        self.folder, self.http_port, self.executable = folder, free_port(), executable
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
        self.process = subprocess.Popen([str(self.executable), str(self.config)], stdout=self.log,
                                        stderr=subprocess.STDOUT)
        wait(lambda: self.health() is not None, 30, "vc-serve's health page")

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
