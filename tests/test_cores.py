"""Pools are sized by the cores this process may use, not the machine's: a scheduler's share is honoured."""

from __future__ import annotations

import os

import pytest
import torch

from vc.cores import usable_cores
from vc.model.trainer import select_device


@pytest.mark.parametrize(("omp", "expected"), [("3", 3), ("4,2", 4), (" 5 ", 5)])
def test_a_thread_count_set_by_the_user_or_by_ray_is_what_is_used(monkeypatch, omp, expected):
    monkeypatch.setenv("OMP_NUM_THREADS", omp)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(64)), raising=False)
    assert usable_cores() == expected


@pytest.mark.parametrize("omp", ["", "0", "-2", "many"])
def test_without_a_usable_thread_count_the_affinity_mask_decides(monkeypatch, omp):
    """taskset, Slurm and container CPU sets give a process some cores of the machine: those are its cores."""
    monkeypatch.setenv("OMP_NUM_THREADS", omp)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {2, 5, 7}, raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 64)
    assert usable_cores() == 3


def test_where_there_is_no_affinity_mask_the_machine_s_cores_are_used(monkeypatch):
    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    monkeypatch.delattr(os, "sched_getaffinity", raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 6)
    assert usable_cores() == 6


@pytest.mark.skipif(torch.cuda.is_available(), reason="the CPU thread count is set only when training on the CPU")
def test_training_on_the_cpu_takes_one_thread_per_usable_core(monkeypatch):
    """A Ray task of one CPU on a many-core node trains with one thread, not one per core of the node."""
    before = torch.get_num_threads()
    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(64)), raising=False)
    try:
        assert select_device().type == "cpu" and torch.get_num_threads() == 1
    finally:
        torch.set_num_threads(before)


@pytest.mark.parametrize(("native", "expected"), [(True, (True, True)), (False, (False, False))])
def test_a_compile_trains_in_bf16_channels_last_where_the_hardware_has_bf16(monkeypatch, native, expected):
    """``auto`` (the default) follows the hardware; explicit settings are kept as given, whatever it has."""
    import vc.stages.config as stages_config

    monkeypatch.setattr(stages_config, "native_bf16", lambda: native)
    resolved = stages_config.TrainSettings().train_config()
    assert (resolved.bf16_autocast, resolved.channels_last) == expected
    explicit = stages_config.TrainSettings(bf16_autocast=False, channels_last=True).train_config()
    assert (explicit.bf16_autocast, explicit.channels_last) == (False, True)


def test_the_cpu_s_bf16_instructions_are_read_from_its_flags(monkeypatch, tmp_path):
    import vc.cores as cores

    info = tmp_path / "cpuinfo"
    info.write_text("model name\t: Test CPU\nflags\t\t: fpu sse2 avx512f avx512_bf16 amx_tile\n")
    monkeypatch.setattr(cores, "Path", lambda _: info)
    cores.cpu_facts.cache_clear()
    try:
        assert cores.cpu_facts() == ("Test CPU", ("avx512_bf16",))
    finally:
        cores.cpu_facts.cache_clear()
