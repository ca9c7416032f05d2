"""Where a compile's units of work run: in this process (the default), or fanned out over a Ray cluster.

A compile has two kinds of unit that are independent of each other:

- a **render shard** (:func:`render_shard`): a pure function of (scene, plan, region, shard index, settings),
  written atomically under its final name only when complete. A worker that dies mid-shard leaves a
  ``.partial`` folder that the shard's next attempt removes; Ray re-runs the task elsewhere, and the dataset has
  the bytes a one-process render gives.
- a **region's training** (:func:`train_region`): checkpointed in the run folder, so a retried task resumes from
  the last checkpoint.

Export and the self-test are seconds and stay with the caller.

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


def make_executor(name: str, address: str | None = None) -> Executor:
    """The executor a command line names: ``in-process`` or ``ray`` (``address``: a cluster to join)."""
    if name == "in-process":
        if address is not None:
            raise InputError(None, "--address", "only with --executor ray")
        return InProcess()
    if name == "ray":
        return RayExecutor(address)
    raise InputError(None, "--executor", f"unknown executor {name!r} (in-process or ray)")


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
    config: Any  # vc.model.train.TrainConfig
    run: Path
    workers: int
    show_progress: bool = False


def train_region(task: RegionTask):
    """Train (or resume) one region's network and evaluate it on its held-out renders."""
    from vc.model.train import RegionTrainer, select_device
    from vc.render.dataset import open_region

    data = open_region(task.dataset, task.region, task.config.held_out_fraction)
    trainer = RegionTrainer(data, task.config, task.run, task.dataset, select_device(), task.workers,
                            show_progress=task.show_progress)
    trainer.train()
    return trainer.evaluate()
