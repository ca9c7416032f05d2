"""The CPU this process runs on: how many cores it may use (the one number the trainer, the renderer and the
runtime size their pools by), and whether it has bfloat16 instructions (which the trainer's ``auto`` compute
setting asks).

``os.cpu_count()`` counts the machine's cores, not this process's. Under anything that hands a process part of a
machine — a Ray task (Ray sets ``OMP_NUM_THREADS`` to the task's CPUs), Slurm, ``taskset``, a container's CPU set
— a pool sized by it puts several threads on each core, and OpenMP's barriers then wait on threads that are not
running (measured here: a training run beside a second process fell from 42 to 5 images/s).
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

#: The x86 instructions that run bfloat16 arithmetic natively; without them PyTorch emulates it, slower than fp32.
BF16_INSTRUCTIONS = ("amx_bf16", "avx512_bf16")


def usable_cores() -> int:
    """The cores this process should use, in the order a user or scheduler would say so:

    1. ``OMP_NUM_THREADS`` when it is a positive integer (the first level of a nested list such as ``4,2``): set
       by the user, or by Ray for a task of that many CPUs;
    2. the size of the process's CPU affinity mask (Linux: taskset, Slurm, container CPU sets);
    3. the machine's core count.
    """
    requested = os.environ.get("OMP_NUM_THREADS", "").split(",")[0].strip()
    if requested.isdigit() and int(requested) > 0:
        return int(requested)
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


@functools.cache
def cpu_facts() -> tuple[str, tuple[str, ...]]:
    """The CPU's model name and which of :data:`BF16_INSTRUCTIONS` it has, from ``/proc/cpuinfo`` (Linux; elsewhere
    ``("unknown", ())``, and the trainer's ``auto`` stays in fp32)."""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return "unknown", ()
    name = next((line.split(":", 1)[1].strip() for line in info.splitlines() if line.startswith("model name")), "?")
    flags = next((line.split(":", 1)[1].split() for line in info.splitlines() if line.startswith("flags")), [])
    return name, tuple(flag for flag in BF16_INSTRUCTIONS if flag in flags)
