"""vc-serve's deployment recipes (packaging/serve/) work as written: the systemd unit passes ``systemd-analyze
verify``, and the container file's install commands, run in a fresh venv, give a runtime without the compiler's
packages that serves a camera's people to a real broker."""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
import venv
from importlib import metadata
from pathlib import Path

import cv2
import pytest
from conftest import REPO, load_script
from serve_factory import marker_bundle, marker_frame
from serve_servers import Broker, Service, Subscriber, needs_broker, wait

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("serve_live")]

RECIPES = REPO / "packaging" / "serve"
SYSTEMD_ANALYZE = Path("/usr/bin/systemd-analyze")
#: What the compiler needs and the service must do without.
COMPILER_ONLY = {"torch", "mitsuba", "drjit", "anny", "trimesh", "openimageio", "colour-science", "matplotlib"}


def _run_instruction(containerfile: Path) -> str:
    """The container file's RUN instruction (continuation lines joined)."""
    text = containerfile.read_text().replace("\\\n", " ")
    runs = [line[len("RUN "):] for line in text.splitlines() if line.startswith("RUN ")]
    assert len(runs) == 1, "the recipe installs in one RUN instruction"
    return runs[0]


@pytest.mark.skipif(not SYSTEMD_ANALYZE.exists(), reason="systemd-analyze is not installed")
def test_the_systemd_unit_passes_systemd_analyze_verify(tmp_path):
    """Verified as installed: its ExecStart pointed at this environment's vc-serve (verify checks the program
    exists). Any warning counts as a failure: verify warns about unknown keys and values but still exits 0."""
    unit = (RECIPES / "vc-serve.service").read_text()
    assert "ExecStart=/opt/vc-serve/bin/vc-serve /etc/vc-serve/serve.yaml" in unit
    installed = tmp_path / "vc-serve.service"
    installed.write_text(unit.replace("/opt/vc-serve/bin/vc-serve", str(Path(sys.executable).parent / "vc-serve")))
    result = subprocess.run([str(SYSTEMD_ANALYZE), "verify", str(installed)], capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr.strip() == "" and result.stdout.strip() == "", result.stderr
    # a typo is caught the same way: the check can fail
    broken = tmp_path / "broken.service"
    broken.write_text(installed.read_text().replace("TimeoutStopSec=", "TimeoutStopSecs="))
    complaint = subprocess.run([str(SYSTEMD_ANALYZE), "verify", str(broken)], capture_output=True, text=True)
    assert "Unknown key 'TimeoutStopSecs'" in complaint.stderr


@pytest.fixture(scope="module")
def container_venv(tmp_path_factory) -> Path:
    """The container file's install commands run in a fresh venv: the wheel from packaging/runtime/build.py for
    /tmp/wheels, the venv's folder for /opt/vc-serve; the distributions this environment has are pinned (a
    constraints file) and pip may use its cache (the image's ``--no-cache-dir`` only keeps the image small)."""
    root = tmp_path_factory.mktemp("container")
    build = load_script(REPO / "packaging" / "runtime" / "build.py", "runtime_build")
    wheels = root / "wheels"
    build.build_wheel(wheels)
    prefix = root / "vc-serve"
    venv.create(prefix, with_pip=True)
    constraints = root / "constraints.txt"
    constraints.write_text("".join(f"{name}=={metadata.version(name)}\n" for name in (
        "numpy", "onnxruntime", "opencv-python-headless", "paho-mqtt", "prometheus-client", "pyyaml", "pydantic",
        "pydantic-core")))
    for command in _run_instruction(RECIPES / "Containerfile").split("&&"):
        words = shlex.split(command.strip())
        if words[:3] == ["python", "-m", "venv"]:
            continue  # made above
        if "pip" in Path(words[0]).name:
            line = command.replace("/opt/vc-serve", str(prefix)).replace("/tmp/wheels", str(wheels)) \
                .replace("--no-cache-dir", "")
            subprocess.run(f"{line} --quiet --disable-pip-version-check -c {constraints}", shell=True, check=True,
                           executable="/bin/bash")
    return prefix / "bin"


def test_the_container_install_holds_the_runtime_and_the_service_without_the_compiler(container_venv, tmp_path):
    listing = subprocess.run([str(container_venv / "python"), "-m", "pip", "list", "--format=json",
                              "--disable-pip-version-check"], capture_output=True, text=True, check=True)
    installed = {package["name"].lower().replace("_", "-") for package in json.loads(listing.stdout)}
    assert {"visual-compiler-runtime", "onnxruntime", "paho-mqtt", "prometheus-client"} <= installed
    assert not installed & COMPILER_ONLY, installed & COMPILER_ONLY
    bad = tmp_path / "serve.yaml"
    bad.write_text("cameras: []\n")
    refused = subprocess.run([str(container_venv / "vc-serve"), str(bad)], capture_output=True, text=True)
    assert refused.returncode == 2 and refused.stderr.startswith(f"error: {bad}: cameras")


@needs_broker
def test_the_container_install_serves_a_cameras_people_to_a_broker(container_venv, bundle, tmp_path):
    marker = marker_bundle(bundle, tmp_path / "markers")
    (tmp_path / "frames").mkdir()
    for k in range(30):
        cv2.imwrite(str(tmp_path / "frames" / f"{k:05d}.png"), marker_frame((128, 64), [(2 + k // 3, 8)]))
    broker = Broker(tmp_path / "broker")
    broker.start()
    try:
        subscriber = Subscriber(broker.port)
        service = Service(tmp_path, marker, str(tmp_path / "frames"), broker.port,
                          executable=container_venv / "vc-serve", camera={"fps": 10})
        service.start()
        try:
            wait(lambda: {"new", "end"} <= {e["type"] for e in subscriber.received()}, 20,
                 "the walker's new and end events at the broker")
        finally:
            assert service.terminate() == 0
        subscriber.close()
    finally:
        broker.stop()
    assert re.search(r"vc-serve: 1 camera\(s\)", service.output())


@needs_broker
def test_the_load_benchmark_measures_capacity_cpu_latency_and_a_soak(bundle, tmp_path):
    """benchmarks/serve_load.py end to end on a short run: a video of a walker at 10 frames/s, one camera and two,
    a 4 s soak; every figure the report gives is there and sane (the real run's figures are committed)."""
    from benchmarks import serve_load

    marker = marker_bundle(bundle, tmp_path / "markers")
    writer = cv2.VideoWriter(str(tmp_path / "walk.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 10, (128, 64))
    for k in range(60):
        writer.write(marker_frame((128, 64), [(2 + (k % 45) // 3, 8)]))
    writer.release()
    out = tmp_path / "report"
    assert serve_load.main([str(marker), "--video", str(tmp_path / "walk.avi"), "--fps", "10", "--max-cameras", "2",
                            "--warmup-s", "2", "--measure-s", "3", "--soak-cameras", "1", "--soak-s", "4",
                            "--out", str(out)]) == 0
    report = json.loads((out / "serve_load.json").read_text())
    assert [point["cameras"] for point in report["capacity"]] == [1, 2] and report["served_cameras"] == 2
    for point in report["capacity"]:
        assert 8 <= point["frames_read_per_s"] <= 11 and point["dropped_share_worst_camera"] < 0.01
        assert 0 < point["cpu_per_camera"] < 2 and point["events"] > 0 and 0 < point["latency_ms_median"] < 1000
    soak = report["soak"]
    assert soak["faults"] == 0 and len(soak["resident_mb"]) >= 2 and abs(soak["growth_after_warmup"]) < 0.5
    assert (out / "serve_load.png").stat().st_size > 0
    assert "Capacity: 2 camera(s)" in (out / "serve_load.md").read_text()
