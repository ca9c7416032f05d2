"""The appliance runtime installs alone: its wheel, in an empty venv, runs a bundle with numpy and onnxruntime.

This replaces a blocklist ("the runtime must not import torch") with the stronger allowlist: the runtime wheel holds
only the modules packaging/runtime/build.py stages, its install pulls only the distributions below, and running a bundle
loads no third-party module but numpy and onnxruntime (and what onnxruntime itself loads).
"""

from __future__ import annotations

import json
import subprocess
import venv
from importlib import metadata
from pathlib import Path

import pytest
from conftest import REPO, load_script

pytestmark = pytest.mark.slow

#: What `pip install visual-compiler-runtime` may install: the runtime, numpy, onnxruntime and onnxruntime's own
#: dependencies (onnxruntime 1.32: flatbuffers, packaging, protobuf; older releases add coloredlogs and sympy).
ALLOWED_DISTRIBUTIONS = {"visual-compiler-runtime", "numpy", "onnxruntime", "flatbuffers", "packaging", "protobuf",
                         "coloredlogs", "humanfriendly", "sympy", "mpmath", "pip", "setuptools"}
#: Third-party top-level modules a bundle run may load.
ALLOWED_MODULES = {"vc", "numpy", "onnxruntime", "google", "flatbuffers", "packaging", "coloredlogs",
                   "humanfriendly", "sympy", "mpmath"}
#: What the compiler needs and an appliance must do without.
ABSENT = ("torch", "mitsuba", "drjit", "anny", "cv2", "OpenImageIO", "trimesh", "tqdm", "cryptography")

RUN_A_BUNDLE = """
import json, sys
import numpy as np
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker
from vc.errors import InputError
from vc.deploy.frames import FrameSource

tracker = Tracker()
with Runtime(sys.argv[1], threads=1) as runtime:
    width, height = runtime.bundle.frame_size
    for time_s in (0.0, 0.1):
        people = tracker.update(runtime(np.full((height, width, 3), 128, np.uint8)), time_s)
try:
    next(iter(FrameSource(sys.argv[2])))
    frames_error = None
except InputError as error:
    frames_error = str(error)
loaded = {name.split(".")[0] for name in sys.modules} - set(sys.stdlib_module_names) - set(sys.builtin_module_names)
absent = []
for name in sys.argv[3:]:
    try:
        __import__(name)
    except ImportError:
        absent.append(name)
print(json.dumps({"people": len(people), "loaded": sorted(m for m in loaded if not m.startswith("_")),
                  "absent": absent, "frames_error": frames_error}))
"""


@pytest.fixture(scope="module")
def runtime_venv(tmp_path_factory) -> Path:
    """An empty venv with only the runtime wheel installed (numpy and onnxruntime pinned to this environment's
    versions, so that pip finds them in its cache)."""
    build = load_script(REPO / "packaging" / "runtime" / "build.py", "runtime_build")
    root = tmp_path_factory.mktemp("runtime")
    wheel = build.build_wheel(root / "dist")
    venv.create(root / "venv", with_pip=True)
    pins = [f"{name}=={metadata.version(name)}" for name in ("numpy", "onnxruntime")]
    python = root / "venv" / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
                    "--only-binary=:all:", str(wheel), *pins], check=True)
    return python


def test_the_runtime_wheel_installs_numpy_and_onnxruntime_only(runtime_venv):
    listing = subprocess.run([str(runtime_venv), "-m", "pip", "list", "--format=json", "--disable-pip-version-check"],
                             capture_output=True, text=True, check=True)
    installed = {package["name"].lower() for package in json.loads(listing.stdout)}
    assert {"visual-compiler-runtime", "numpy", "onnxruntime"} <= installed
    assert installed <= ALLOWED_DISTRIBUTIONS, f"installed beyond the allowlist: {installed - ALLOWED_DISTRIBUTIONS}"


def test_the_runtime_wheel_runs_a_bundle_with_numpy_and_onnxruntime_only(runtime_venv, bundle, tmp_path):
    image = tmp_path / "frame.png"
    image.write_bytes(b"not read: OpenCV is absent")
    result = subprocess.run([str(runtime_venv), "-c", RUN_A_BUNDLE, str(bundle), str(image), *ABSENT],
                            capture_output=True, text=True, check=False, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["people"] >= 0
    assert set(report["loaded"]) <= ALLOWED_MODULES, f"loaded beyond the allowlist: {report['loaded']}"
    assert report["absent"] == list(ABSENT)
    assert "'video' extra" in report["frames_error"]


def test_the_runtime_wheel_ships_the_c_decoder_as_source_and_builds_it_where_installed(runtime_venv):
    default = [str(runtime_venv), "-c", "from vc.deploy import native; print(native.default_decoder())"]
    assert subprocess.run(default, capture_output=True, text=True, check=True).stdout.strip() == "numpy"
    built = subprocess.run([str(runtime_venv), "-m", "vc.deploy.native"], capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    assert subprocess.run(default, capture_output=True, text=True, check=True).stdout.strip() == "c"
