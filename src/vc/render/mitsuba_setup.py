"""Import Mitsuba with the right variant, once per process.

The variant is global state in Mitsuba and every plugin dictionary is interpreted by it, so it is chosen in
exactly one place: ``cuda_ad_rgb`` when Dr.Jit can initialise a CUDA device, otherwise ``llvm_ad_rgb`` on the
CPU. The CPU backend must load LLVM 19 (LLVM 14-16 abort the process on the first path-tracing kernel), so
``DRJIT_LIBLLVM_PATH`` is pointed at Debian's libLLVM-19 before Dr.Jit is imported, unless the user set it.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path
from types import ModuleType

from vc.cores import usable_cores

#: Where Debian/Ubuntu's ``libllvm19`` package puts the shared library Dr.Jit's CPU backend needs.
LIBLLVM_19 = Path("/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
GPU_VARIANT = "cuda_ad_rgb"
CPU_VARIANT = "llvm_ad_rgb"


def _point_drjit_at_llvm_19() -> None:
    if "DRJIT_LIBLLVM_PATH" not in os.environ and LIBLLVM_19.is_file():
        os.environ["DRJIT_LIBLLVM_PATH"] = str(LIBLLVM_19)


@functools.cache
def mitsuba() -> ModuleType:
    """The ``mitsuba`` module with its variant set (``cuda_ad_rgb`` if a GPU is usable, else ``llvm_ad_rgb``)."""
    _point_drjit_at_llvm_19()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(GPU_VARIANT if dr.has_backend(dr.JitBackend.CUDA) else CPU_VARIANT)
    if mi.variant() == CPU_VARIANT:
        dr.set_thread_count(usable_cores())  # Dr.Jit's pool would take every core of the machine
    return mi
