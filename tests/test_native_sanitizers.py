"""The C decoder under AddressSanitizer and UndefinedBehaviorSanitizer: tests/hard_cases/test_native_decode.py (random,
degenerate and hostile heat maps against numpy's decoder, maps of every size) run again on a build with both, every
finding fatal (``-fno-sanitize-recover``), loaded in its own Python with the AddressSanitizer runtime preloaded."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from vc.deploy import native

REPO = Path(__file__).resolve().parents[1]
COMPILER = os.environ.get("CC", "cc")


def _runtime(name: str) -> str:
    """The compiler's own copy of a sanitizer runtime (what it links the build against)."""
    path = subprocess.run([COMPILER, f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
    if not Path(path).is_file():
        pytest.skip(f"{COMPILER} has no {name} (Debian: gcc brings it; make install installs gcc)")
    return str(Path(path).resolve())


@pytest.mark.slow
def test_the_decoder_meets_every_hostile_map_without_a_sanitizer_finding(tmp_path):
    library = native.build(tmp_path / "libvc_decode_sanitized.so", sanitize=True, compiler=COMPILER)
    symbols = subprocess.run(["nm", "-D", str(library)], capture_output=True, text=True, check=True).stdout
    assert "__asan_" in symbols and "__ubsan_" in symbols  # the build under test is the sanitized one
    environment = {**os.environ, native.LIBRARY_VARIABLE: str(library), "LD_PRELOAD": _runtime("libasan.so"),
                   "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=1", "UBSAN_OPTIONS": "print_stacktrace=1"}
    result = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist",
                             "-W", "ignore::RuntimeWarning", "tests/hard_cases/test_native_decode.py"],
                            cwd=REPO, env=environment, capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-4000:]
    assert " passed" in result.stdout and "skipped" not in result.stdout
