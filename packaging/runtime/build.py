"""Build the appliance runtime wheel (``visual-compiler-runtime``) from this repository's own modules.

    python packaging/runtime/build.py [-o dist]

The runtime is not a copy: the modules of ``src/vc`` in :data:`RUNTIME_MODULES` are staged, as they are, into the
packages ``vc`` and ``vc.deploy`` beside this folder's ``pyproject.toml``, and that staged project is built with pip.
Only these modules go in, so an import of anything else (torch, mitsuba, the compiler's own layers) fails on an
appliance exactly as it fails in tests/test_runtime_wheel.py, which installs the wheel into an empty venv.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[2]
PACKAGE = REPOSITORY / "src" / "vc"
HERE = Path(__file__).resolve().parent

#: Modules of ``src/vc`` staged into the wheel, at the same place.
RUNTIME_MODULES = (
    "__init__.py", "cores.py", "errors.py", "keypoints.py",
    # the camera model (numpy only): a bundle's people placed on the ground (deploy/zones.py)
    "calibration/__init__.py", "calibration/camera.py", "calibration/distortion.py",
    "deploy/__init__.py", "deploy/areas.py", "deploy/boxes.py", "deploy/bundle.py", "deploy/decode.py",
    "deploy/crop_pose.py", "deploy/engines.py", "deploy/exposure.py", "deploy/facing.py", "deploy/fitness.py",
    "deploy/frames.py", "deploy/heatmaps.py",
    # the C decoder: its ctypes binding and its sources, built where the wheel is installed (python -m vc.deploy.native)
    "deploy/native.py", "deploy/native/vc_decode.h", "deploy/native/vc_decode.c", "deploy/native/vc_bundle.c",
    "deploy/registration.py", "deploy/runtime.py", "deploy/signing.py", "deploy/tracking.py", "deploy/veil.py",
    "deploy/zones.py",
    # vc-serve (the `serve` extra): the service and its command, with the commands' shared error contract
    "serve/__init__.py", "serve/config.py", "serve/events.py", "serve/health.py", "serve/mqtt.py", "serve/queue.py",
    "serve/service.py", "serve/sources.py",
    "cli/__init__.py", "cli/common.py", "cli/serve.py",
)


def build_wheel(output: Path) -> Path:
    """Build the runtime wheel into ``output`` and return its path."""
    output = Path(output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="vc-runtime-") as staging:
        stage = Path(staging)
        for name in ("pyproject.toml", "README.md"):
            shutil.copy2(HERE / name, stage / name)
        for module in RUNTIME_MODULES:
            (stage / "vc" / module).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(PACKAGE / module, stage / "vc" / module)
        before = set(output.glob("*.whl"))
        subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
                        "--wheel-dir", str(output), str(stage)], check=True)
    built = sorted(set(output.glob("visual_compiler_runtime-*.whl")) - before) or \
        sorted(output.glob("visual_compiler_runtime-*.whl"))
    return built[-1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", type=Path, default=REPOSITORY / "dist", help="wheel folder (default: dist)")
    wheel = build_wheel(parser.parse_args(argv).output)
    print(f"built {wheel}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
