"""Where a compile's work runs: the in-process executor, worker processes of this machine, and a command line
that asks for a cluster wrongly or for two scenes of one name gets one line and exit status 2 before anything is
written (the Ray cluster and the processes' renders are tested end to end in tests/test_compile.py)."""

from __future__ import annotations

import math
import shutil

import pytest

from vc.cli import compile as compile_cli
from vc.errors import InputError
from vc.stages.executors import InProcess, LocalProcesses, make_executor


def test_in_process_runs_every_item_once_in_order():
    seen = []
    results = list(InProcess().map_unordered(lambda item: seen.append(item) or item * 2, [3, 1, 2]))
    assert results == [(0, 6), (1, 2), (2, 4)] and seen == [3, 1, 2]


def test_worker_processes_run_every_item_once():
    results = dict(LocalProcesses(2).map_unordered(math.factorial, [5, 3, 4, 0]))
    assert results == {0: 120, 1: 6, 2: 24, 3: 1}
    assert dict(LocalProcesses(3).map_unordered(math.factorial, [6], cpus=8)) == {0: 720}  # larger than the pool


def test_an_address_needs_the_ray_executor():
    with pytest.raises(InputError, match="only with --executor ray"):
        make_executor("in-process", "auto")
    with pytest.raises(InputError, match="only with --executor ray"):
        make_executor("processes", "auto")


def test_a_process_count_needs_the_processes_executor_and_one_process_at_least():
    with pytest.raises(InputError, match="only with --executor processes"):
        make_executor("in-process", processes=4)
    with pytest.raises(InputError, match="at least 1"):
        make_executor("processes", processes=0)
    assert make_executor("processes", processes=3) == LocalProcesses(3)


def test_scenes_compiled_together_need_their_own_names(tmp_path, capsys):
    copy = tmp_path / "copy"
    shutil.copytree("examples/scenes/demo", copy)
    code = compile_cli.main(["examples/scenes/demo/scene.yaml", str(copy / "scene.yaml"), "-o", str(tmp_path / "out"),
                             "--budget", "quick"])
    error = capsys.readouterr().err
    assert code == 2 and error.count("\n") == 1 and "need their own names" in error
    assert not (tmp_path / "out").exists()


def test_an_address_without_ray_executor_is_one_line(tmp_path, capsys):
    code = compile_cli.main(["examples/scenes/demo/scene.yaml", "-o", str(tmp_path / "out"), "--address", "auto"])
    error = capsys.readouterr().err
    assert code == 2 and "--address" in error and not (tmp_path / "out").exists()
