"""How many cores this process may use: the one number the trainer, the renderer and the runtime size their pools by.

``os.cpu_count()`` counts the machine's cores, not this process's. Under anything that hands a process part of a
machine — a Ray task (Ray sets ``OMP_NUM_THREADS`` to the task's CPUs), Slurm, ``taskset``, a container's CPU set
— a pool sized by it puts several threads on each core, and OpenMP's barriers then wait on threads that are not
running (measured here: a training run beside a second process fell from 42 to 5 images/s).
"""

from __future__ import annotations

import os


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
