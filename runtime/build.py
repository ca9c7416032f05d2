"""Build the appliance runtime wheel (``visual-compiler-runtime``) from this repository's own modules.

    python runtime/build.py [-o dist]

The runtime is not a copy: the modules in :data:`RUNTIME_MODULES` are staged, as they are, into the packages
``vc`` and ``vc.deploy`` beside ``runtime/pyproject.toml``, and that staged project is built with pip. Only these
modules go in, so an import of anything else (torch, mitsuba, the compiler's own layers) fails on an appliance
exactly as it fails in tests/test_runtime_wheel.py, which installs the wheel into an empty venv.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent

#: Repository file -> its place in the wheel.
RUNTIME_MODULES = {
    "vc/__init__.py": "vc/__init__.py",
    "vc/cores.py": "vc/cores.py",
    "vc/errors.py": "vc/errors.py",
    "vc/keypoints.py": "vc/keypoints.py",
    "deploy/__init__.py": "vc/deploy/__init__.py",
    "deploy/areas.py": "vc/deploy/areas.py",
    "deploy/boxes.py": "vc/deploy/boxes.py",
    "deploy/bundle.py": "vc/deploy/bundle.py",
    "deploy/decode.py": "vc/deploy/decode.py",
    "deploy/frames.py": "vc/deploy/frames.py",
    "deploy/heatmaps.py": "vc/deploy/heatmaps.py",
    "deploy/runtime.py": "vc/deploy/runtime.py",
    "deploy/signing.py": "vc/deploy/signing.py",
    "deploy/tracking.py": "vc/deploy/tracking.py",
}


def build_wheel(output: Path) -> Path:
    """Build the runtime wheel into ``output`` and return its path."""
    output = Path(output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="vc-runtime-") as staging:
        stage = Path(staging)
        for name in ("pyproject.toml", "README.md"):
            shutil.copy2(REPOSITORY / "runtime" / name, stage / name)
        for source, target in RUNTIME_MODULES.items():
            (stage / target).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(REPOSITORY / source, stage / target)
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
