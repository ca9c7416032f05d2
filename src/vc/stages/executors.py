"""Where a compile's units of work run: in this process (the default), in worker processes of this machine, or
fanned out over a Ray cluster.

A compile has two kinds of unit that are independent of each other:

- a **render shard** (:func:`render_shard`): a pure function of (scene, plan, region, shard index, settings),
  written atomically under its final name only when complete. A worker that dies mid-shard leaves a
  ``.partial`` folder that the shard's next attempt removes; Ray re-runs the task elsewhere, and the dataset has
  the bytes a one-process render gives.
- a **region's training** (:func:`train_region`): checkpointed in the run folder, so a retried task resumes from
  the last checkpoint.

Export and the self-test are seconds and stay with the caller.

Worker processes of this machine (:class:`LocalProcesses`, the standard library's process pool) are for a host
that one process cannot keep busy: a sample's renderer is first a Python trace and kernel launches (about 17 ms
however few its rays, docs/compile.md), so on a GPU, or on many cores, several renderers at once go faster than one.
They need nothing installed; a worker that dies fails the stage, and running the compile again resumes from the
shards already written.

Ray (https://docs.ray.io) is the distributed engine: an optional extra (``pip install 'visual-compiler[ray]'``),
imported only when ``--executor ray`` asks for it. Its tasks are retried when their worker process or node dies
(``max_retries``), which is the whole fault model a shard needs. Workers read the scene and write the dataset and
the run folder by path: on a multi-machine cluster the output folder and the scene must be on a file system every
node mounts at the same path (NFS, a shared volume), as a render farm's is.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any, Protocol

from vc.cores import usable_cores
from vc.errors import InputError

#: Environment variables a worker needs to run a stage as this process would (Mitsuba's LLVM backend).
FORWARDED_ENVIRONMENT = ("DRJIT_LIBLLVM_PATH",)
#: Attempts of a task beyond the first when its worker dies (Ray's ``max_retries``).
TASK_RETRIES = 3


class Executor(Protocol):
    """Runs ``function`` on every item and yields ``(index, result)`` as each finishes (in any order)."""

    name: str

    def map_unordered(self, function: Callable[[Any], Any], items: Sequence[Any], cpus: float = 1.0
                      ) -> Iterator[tuple[int, Any]]: ...


class InProcess:
    """Each item in turn, in this process: the default, and the reference a cluster's bytes are compared with."""

    name = "in-process"

    def map_unordered(self, function: Callable[[Any], Any], items: Sequence[Any], cpus: float = 1.0
                      ) -> Iterator[tuple[int, Any]]:
        for index, item in enumerate(items):
            yield index, function(item)


@dataclass
class LocalProcesses:
    """Items in up to ``processes`` worker processes of this machine, a task of ``cpus`` CPUs taking that many of
    them. Spawned, not forked: each worker starts its own renderer and GPU context, which a fork of a process that
    has one cannot. One pool per call, so that a worker's cached renderers serve every shard of that call."""

    processes: int
    name: str = "processes"

    def __post_init__(self) -> None:
        if self.processes < 1:
            raise InputError(None, "--processes", f"must be at least 1, got {self.processes}")

    def map_unordered(self, function: Callable[[Any], Any], items: Sequence[Any], cpus: float = 1.0
                      ) -> Iterator[tuple[int, Any]]:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor, as_completed

        at_once = max(1, min(len(items), int(self.processes // max(cpus, 1.0))))
        threads = max(1, usable_cores() // at_once)
        with ProcessPoolExecutor(at_once, mp_context=multiprocessing.get_context("spawn"),
                                 initializer=_use_threads, initargs=(threads,)) as pool:
            futures = {pool.submit(function, item): index for index, item in enumerate(items)}
            for future in as_completed(futures):
                yield futures[future], future.result()


def _use_threads(count: int) -> None:
    """A worker's share of the cores: read by torch and onnxruntime when the task imports them (and by
    :func:`vc.cores.usable_cores`), as Ray sets it for a task of that many CPUs."""
    os.environ["OMP_NUM_THREADS"] = str(count)


@dataclass
class RayExecutor:
    """Items as Ray tasks of ``cpus`` CPUs each, retried on worker death.

    ``address``: a running cluster (``auto``, ``ray://host:10001``, ``host:6379``), or None to start a local one
    on this machine with ``local_cpus`` CPUs (all of them when None)."""

    address: str | None = None
    local_cpus: int | None = None
    name: str = "ray"

    def __post_init__(self) -> None:
        try:
            import ray
        except ImportError:
            raise InputError(None, "--executor", "ray is not installed: pip install 'visual-compiler[ray]'") from None
        self._ray = ray
        if not ray.is_initialized():
            environment = {key: os.environ[key] for key in FORWARDED_ENVIRONMENT if key in os.environ}
            ray.init(address=self.address, num_cpus=self.local_cpus if self.address is None else None,
                     include_dashboard=False, log_to_driver=False, runtime_env={"env_vars": environment})
        self._remote = cache(lambda function, cpus: ray.remote(num_cpus=cpus, max_retries=TASK_RETRIES,
                                                               retry_exceptions=False)(function))

    def map_unordered(self, function: Callable[[Any], Any], items: Sequence[Any], cpus: float = 1.0
                      ) -> Iterator[tuple[int, Any]]:
        remote = self._remote(function, cpus)
        pending = {remote.remote(item): index for index, item in enumerate(items)}
        while pending:
            done, _ = self._ray.wait(list(pending), num_returns=1)
            for reference in done:
                yield pending.pop(reference), self._ray.get(reference)

    def shutdown(self) -> None:
        self._ray.shutdown()


#: The executors a command line can name.
EXECUTORS = ("in-process", "processes", "ray")


def make_executor(name: str, address: str | None = None, processes: int | None = None) -> Executor:
    """The executor a command line names: ``in-process``, ``processes`` (``processes`` workers, every usable core
    when None) or ``ray`` (``address``: a cluster to join)."""
    if address is not None and name != "ray":
        raise InputError(None, "--address", "only with --executor ray")
    if processes is not None and name != "processes":
        raise InputError(None, "--processes", "only with --executor processes")
    if name == "in-process":
        return InProcess()
    if name == "processes":
        return LocalProcesses(processes if processes is not None else usable_cores())
    if name == "ray":
        return RayExecutor(address)
    raise InputError(None, "--executor", f"unknown executor {name!r} ({', '.join(EXECUTORS)})")


# --- the units of work: module-level functions of picklable arguments, so that any worker can run them ---------


@dataclass(frozen=True)
class ShardTask:
    request: Any  # vc.render.job.RenderRequest (scene, plan and settings travel with it)
    region: str
    shard: Any  # vc.render.dataset.Shard


@cache
def _bodies():
    """One body model per worker process: loading it takes seconds, and a worker renders many shards."""
    from vc.render.bodies import BodyModel

    return BodyModel()


#: The region synthesizers a worker process built, by what decides them: a worker that renders many shards of one
#: region (the usual case) builds its renderer and reads the background once, not once a shard.
_synthesizers: dict[tuple, Any] = {}
#: Synthesizers a worker keeps (a few regions of a few scenes in flight).
KEPT_SYNTHESIZERS = 8


def _synthesizer(request, region):
    from vc.render.synthesis import RegionSynthesizer

    key = (request.scene.content_hash, region.name, request.settings,
           json.dumps(request.plan.to_dict(), sort_keys=True, default=str))
    if key not in _synthesizers:
        if len(_synthesizers) >= KEPT_SYNTHESIZERS:
            _synthesizers.pop(next(iter(_synthesizers)))
        _synthesizers[key] = RegionSynthesizer(request.scene, region, _bodies(), request.settings, request.plan)
    return _synthesizers[key]


def render_shard(task: ShardTask) -> dict:
    """Render one shard into the dataset (atomically); returns its counts and the seconds it took."""
    from vc.render import dataset
    from vc.render.job import shard_info

    start = time.perf_counter()
    region = next(region for region in task.request.regions if region.name == task.region)
    synthesizer = _synthesizer(task.request, region)
    samples = (synthesizer.sample(index) for index in range(task.shard.start, task.shard.stop))
    counts = dataset.write_shard(task.request.output, task.shard, samples, shard_info(task.request, region))
    return {**counts, "seconds": time.perf_counter() - start}


@dataclass(frozen=True)
class RegionTask:
    dataset: Path
    region: str
    config: Any  # vc.model.trainer.TrainConfig
    run: Path
    workers: int
    show_progress: bool = False


def train_region(task: RegionTask):
    """Train (or resume) one region's network and evaluate it on its held-out renders."""
    from vc.model.trainer import RegionTrainer, select_device
    from vc.render.dataset import open_region

    data = open_region(task.dataset, task.region, task.config.held_out_fraction)
    trainer = RegionTrainer(data, task.config, task.run, task.dataset, select_device(), task.workers,
                            show_progress=task.show_progress)
    trainer.train()
    return trainer.evaluate()
