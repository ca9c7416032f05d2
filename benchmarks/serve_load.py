"""vc-serve under load: how many cameras one machine serves, the CPU each takes, memory over a long run, and event
latency.

    python -m benchmarks.serve_load BUNDLE --video vtest.avi [--fps 7] [--max-cameras 8] [--warmup-s 20]
                                    [--measure-s 60] [--soak-cameras 4] [--soak-s 3600] [--out DIR]

1. **Capacity.** For N = 1, 2, ... cameras, one ``vc-serve`` process runs N cameras, each the video looped at
   ``--fps`` (a video file played as a camera: its decoding is counted, a network's is not), and a local mosquitto
   takes the events. After ``--warmup-s``, over ``--measure-s``, each camera's frames dropped per frame read (from
   ``/metrics``), the process's CPU seconds per second per camera (``/proc/PID/stat``, all its threads), its
   resident memory, and the latency of its events: from the capture of the frame an event comes from (its ``time``)
   to its arrival at a subscriber, on the same machine's clock (``new`` and ``update`` events; an ``end`` is sent a
   second after the frame it describes). The sweep stops at the first N at which a camera drops 1 % or more; the
   capacity is the N before it.
2. **Soak.** ``--soak-cameras`` cameras for ``--soak-s``, resident memory sampled every 10 s. Growth is measured from
   the end of the warm-up (the first 10 % of the run) to the end.

Writes ``serve_load.json``, ``serve_load.md`` and ``serve_load.png`` to ``--out``, with the machine's CPU and cores:
figures from one machine say nothing about another.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import paho.mqtt.client as paho  # noqa: E402
from prometheus_client.parser import text_string_to_metric_families  # noqa: E402

from benchmarks import display_path, results_folder  # noqa: E402
from vc.cores import cpu_facts, usable_cores  # noqa: E402

#: A camera that drops this share of its frames or more is beyond what the machine serves.
MAX_DROPPED = 0.01
SAMPLE_S = 10.0  # the soak's memory samples
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class _Broker:
    """mosquitto on a free port, for the run."""

    def __init__(self, folder: Path) -> None:
        executable = shutil.which("mosquitto") or "/usr/sbin/mosquitto"
        self.port = _free_port()
        (folder / "mosquitto.conf").write_text(f"listener {self.port} 127.0.0.1\nallow_anonymous true\n")
        self.process = subprocess.Popen([executable, "-c", str(folder / "mosquitto.conf")],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            with socket.socket() as probe:
                if probe.connect_ex(("127.0.0.1", self.port)) == 0:
                    return
            time.sleep(0.1)
        raise RuntimeError("mosquitto did not start")

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait(10)


class _Latency:
    """A subscriber recording each event's latency: arrival time less the capture time of its frame."""

    def __init__(self, port: int) -> None:
        self.samples: list[float] = []
        self.lock = threading.Lock()
        self.client = paho.Client(paho.CallbackAPIVersion.VERSION2, client_id=f"serve-load-{port}")
        self.client.on_connect = lambda client, *_: client.subscribe("vc/+/events", qos=1)
        self.client.on_message = self._received
        self.client.connect("127.0.0.1", port)
        self.client.loop_start()

    def _received(self, client, userdata, message) -> None:
        arrived = time.time()
        event = json.loads(message.payload)
        if event["type"] != "end":
            with self.lock:
                self.samples.append(arrived - event["time"])

    def take(self) -> list[float]:
        with self.lock:
            samples, self.samples = self.samples, []
        return samples

    def close(self) -> None:
        self.client.disconnect()
        self.client.loop_stop()


class _Service:
    """``vc-serve`` with ``cameras`` cameras playing ``video`` at ``fps``."""

    def __init__(self, folder: Path, bundle: Path, video: Path, fps: float, cameras: int, broker: int) -> None:
        self.http = _free_port()
        config = {"cameras": [{"name": f"cam{k}", "bundle": str(bundle), "source": str(video), "loop": True,
                               "fps": fps, "threads": 1} for k in range(cameras)],
                  "mqtt": {"host": "127.0.0.1", "port": broker},
                  "events": {"queue": str(folder / f"queue{cameras}.sqlite")},
                  "http": {"host": "127.0.0.1", "port": self.http}}
        path = folder / f"serve{cameras}.yaml"
        path.write_text(json.dumps(config))
        self.log = open(folder / f"serve{cameras}.log", "w")
        self.process = subprocess.Popen([str(Path(sys.executable).parent / "vc-serve"), str(path)],
                                        stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            try:
                self.metrics()
                return
            except OSError:
                time.sleep(0.2)
        raise RuntimeError(f"vc-serve did not start: see {folder / f'serve{cameras}.log'}")

    def metrics(self) -> dict[tuple[str, str], float]:
        """Every sample of /metrics by (name, camera label)."""
        with urllib.request.urlopen(f"http://127.0.0.1:{self.http}/metrics", timeout=5) as answer:
            text = answer.read().decode()
        return {(sample.name, sample.labels.get("camera", "")): sample.value
                for family in text_string_to_metric_families(text) for sample in family.samples}

    def cpu_seconds(self) -> float:
        fields = Path(f"/proc/{self.process.pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # utime, stime

    def resident_mb(self) -> float:
        for line in Path(f"/proc/{self.process.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return float("nan")

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait(60)
        self.log.close()


def _percentile_ms(samples: list[float], q: float) -> float | None:
    return round(float(np.percentile(samples, q)) * 1e3, 1) if samples else None


def measure_cameras(folder: Path, bundle: Path, video: Path, fps: float, cameras: int, warmup_s: float,
                    measure_s: float) -> dict:
    """One point of the capacity sweep (module docstring, 1)."""
    broker = _Broker(folder)
    latency = _Latency(broker.port)
    service = _Service(folder, bundle, video, fps, cameras, broker.port)
    try:
        time.sleep(warmup_s)
        before, cpu_before, start = service.metrics(), service.cpu_seconds(), time.monotonic()
        latency.take()
        time.sleep(measure_s)
        after, cpu_after, elapsed = service.metrics(), service.cpu_seconds(), time.monotonic() - start
        samples = latency.take()
        resident = service.resident_mb()
    finally:
        service.stop()
        latency.close()
        broker.stop()
    names = [f"cam{k}" for k in range(cameras)]

    def delta(metric: str, camera: str) -> float:
        return after.get((metric, camera), 0.0) - before.get((metric, camera), 0.0)

    read = {name: delta("vc_frames_read_total", name) for name in names}
    dropped = {name: delta("vc_frames_dropped_total", name) for name in names}
    run = {name: delta("vc_frames_run_total", name) for name in names}
    worst = max(dropped[name] / max(read[name], 1.0) for name in names)
    return {"cameras": cameras, "seconds": round(elapsed, 1),
            "frames_read_per_s": round(sum(read.values()) / elapsed / cameras, 2),
            "frames_run_per_s": round(sum(run.values()) / elapsed / cameras, 2),
            "dropped_share_worst_camera": round(worst, 4),
            "dropped_share": {name: round(dropped[name] / max(read[name], 1.0), 4) for name in names},
            "cpu_per_camera": round((cpu_after - cpu_before) / elapsed / cameras, 3),
            "cpu_total": round((cpu_after - cpu_before) / elapsed, 3), "resident_mb": round(resident, 1),
            "events": len(samples), "latency_ms_median": _percentile_ms(samples, 50),
            "latency_ms_p99": _percentile_ms(samples, 99), "served": worst < MAX_DROPPED}


def soak(folder: Path, bundle: Path, video: Path, fps: float, cameras: int, seconds: float) -> dict:
    """The soak (module docstring, 2)."""
    broker = _Broker(folder)
    latency = _Latency(broker.port)
    service = _Service(folder, bundle, video, fps, cameras, broker.port)
    samples, start = [], time.monotonic()
    try:
        while (elapsed := time.monotonic() - start) < seconds:
            samples.append((round(elapsed, 1), round(service.resident_mb(), 1)))
            time.sleep(min(SAMPLE_S, max(0.0, seconds - elapsed)))
        final = service.metrics()
        samples.append((round(time.monotonic() - start, 1), round(service.resident_mb(), 1)))
        events = latency.take()
    finally:
        service.stop()
        latency.close()
        broker.stop()
    warm = next(mb for t, mb in samples if t >= 0.1 * seconds)
    names = [f"cam{k}" for k in range(cameras)]
    read = sum(final.get(("vc_frames_read_total", name), 0.0) for name in names)
    dropped = sum(final.get(("vc_frames_dropped_total", name), 0.0) for name in names)
    return {"cameras": cameras, "seconds": seconds, "resident_mb": samples, "resident_mb_after_warmup": warm,
            "resident_mb_end": samples[-1][1], "growth_after_warmup": round(samples[-1][1] / warm - 1, 4),
            "dropped_share": round(dropped / max(read, 1.0), 4), "frames_read": int(read),
            "faults": int(sum(final.get(("vc_frame_faults_total", name), 0.0) for name in names)),
            "events": len(events), "latency_ms_median": _percentile_ms(events, 50),
            "latency_ms_p99": _percentile_ms(events, 99)}


def _markdown(report: dict) -> str:
    lines = [f"# vc-serve under load: {report['bundle']}, {report['video']} at {report['fps']:g} frames/s a camera",
             "", f"Machine: {report['machine']['cpu']}, {report['machine']['cores']} usable cores. "
             f"Command: `{report['command']}`", "",
             "| cameras | frames read / s a camera | run / s a camera | dropped (worst camera) | CPU s/s a camera | "
             "resident MB | events | latency median / p99 ms |", "|---|---|---|---|---|---|---|---|"]
    for point in report["capacity"]:
        lines.append(f"| {point['cameras']} | {point['frames_read_per_s']} | {point['frames_run_per_s']} | "
                     f"{100 * point['dropped_share_worst_camera']:.2f} % | {point['cpu_per_camera']} | "
                     f"{point['resident_mb']} | {point['events']} | {point['latency_ms_median']} / "
                     f"{point['latency_ms_p99']} |")
    lines += ["", f"**Capacity: {report['served_cameras']} camera(s)** at {report['fps']:g} frames/s with under "
              f"{100 * MAX_DROPPED:g} % of frames dropped."]
    if report.get("soak"):
        soak_report = report["soak"]
        lines += ["", f"Soak: {soak_report['cameras']} cameras for {soak_report['seconds']:.0f} s: resident memory "
                  f"{soak_report['resident_mb_after_warmup']} MB after the warm-up, {soak_report['resident_mb_end']} "
                  f"MB at the end (growth {100 * soak_report['growth_after_warmup']:+.1f} %); frames dropped "
                  f"{100 * soak_report['dropped_share']:.1f} %, {soak_report['faults']} faults; event latency "
                  f"median {soak_report['latency_ms_median']} ms, p99 {soak_report['latency_ms_p99']} ms."]
    return "\n".join(lines) + "\n"


def _plot(report: dict, path: Path) -> None:
    panels = 2 if report.get("soak") else 1
    figure, axes = plt.subplots(1, panels, figsize=(6 * panels, 4), squeeze=False)
    cameras = [p["cameras"] for p in report["capacity"]]
    left = axes[0][0]
    left.plot(cameras, [100 * p["dropped_share_worst_camera"] for p in report["capacity"]], "o-", label="dropped %")
    left.axhline(100 * MAX_DROPPED, color="grey", linestyle=":")
    left.set_xlabel("cameras")
    left.set_ylabel("frames dropped, worst camera (%)")
    twin = left.twinx()
    twin.plot(cameras, [p["cpu_per_camera"] for p in report["capacity"]], "s--", color="tab:orange")
    twin.set_ylabel("CPU seconds per second per camera", color="tab:orange")
    left.set_title(f"{report['fps']:g} frames/s a camera, {report['machine']['cores']} cores")
    if report.get("soak"):
        right = axes[0][1]
        times, megabytes = zip(*report["soak"]["resident_mb"], strict=True)
        right.plot(np.array(times) / 60, megabytes)
        right.set_xlabel("minutes")
        right.set_ylabel("resident memory (MB)")
        right.set_title(f"soak: {report['soak']['cameras']} cameras")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bundle", type=Path, help="a vc-export bundle of the video's camera")
    parser.add_argument("--video", type=Path, required=True, help="the camera's video, looped as each camera")
    parser.add_argument("--fps", type=float, default=7.0)
    parser.add_argument("--max-cameras", type=int, default=8)
    parser.add_argument("--warmup-s", type=float, default=20.0)
    parser.add_argument("--measure-s", type=float, default=60.0)
    parser.add_argument("--soak-cameras", type=int, default=4)
    parser.add_argument("--soak-s", type=float, default=3600.0, help="0: no soak")
    parser.add_argument("--out", type=Path, default=results_folder("serve_load"))
    args = parser.parse_args(argv)
    report = {"bundle": display_path(args.bundle), "video": display_path(args.video), "fps": args.fps,
              "machine": {"cpu": cpu_facts()[0], "cores": usable_cores()},
              "command": f"python -m benchmarks.serve_load {display_path(args.bundle)} --video "
                         f"{display_path(args.video)} --fps {args.fps:g} --max-cameras {args.max_cameras} --warmup-s "
                         f"{args.warmup_s:g} --measure-s {args.measure_s:g} --soak-cameras {args.soak_cameras} "
                         f"--soak-s {args.soak_s:g}",
              "capacity": []}
    with tempfile.TemporaryDirectory(prefix="serve-load-") as scratch:
        for cameras in range(1, args.max_cameras + 1):
            point = measure_cameras(Path(scratch), args.bundle, args.video, args.fps, cameras, args.warmup_s,
                                    args.measure_s)
            report["capacity"].append(point)
            print(f"{cameras} camera(s): dropped {100 * point['dropped_share_worst_camera']:.2f} % (worst), CPU "
                  f"{point['cpu_per_camera']} s/s a camera, {point['resident_mb']} MB, latency "
                  f"{point['latency_ms_median']} / {point['latency_ms_p99']} ms", flush=True)
            if not point["served"]:
                break
        report["served_cameras"] = max([p["cameras"] for p in report["capacity"] if p["served"]], default=0)
        if args.soak_s > 0:
            report["soak"] = soak(Path(scratch), args.bundle, args.video, args.fps, args.soak_cameras, args.soak_s)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "serve_load.json").write_text(json.dumps(report, indent=1) + "\n")
    (args.out / "serve_load.md").write_text(_markdown(report))
    _plot(report, args.out / "serve_load.png")
    print(_markdown(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
