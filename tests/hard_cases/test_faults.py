"""Faults lose nothing (issue 21): a compile killed with SIGKILL in its render, training and export stages resumes
to the bytes of one never stopped; a full disk stops a stage with one line and keeps what was finished; damaged
shards and checkpoints are found by their checksums, and re-made (renders) or refused (training), never used.

The compiles run as separate processes (a SIGKILL must hit a real process, data-loader workers included) on the
demo scene at a toy budget with enough training steps for a kill to land mid-stage. The kill points are read from
what the compile has written, so they do not depend on the machine's speed."""

from __future__ import annotations

import hashlib
import json
import os
import resource
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import torch
from conftest import write_compile_config

from vc.errors import InputError
from vc.model.trainer import checkpoint_path, load_checkpoint
from vc.render.dataset import CHECKSUMS, open_region

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("anny")]

SCENE = "examples/scenes/demo/scene.yaml"
#: Small, but with training long enough (two regions of 12 steps of 16 windows) to be killed in the middle.
FAULT_BUDGET = {"render": {"samples": 12, "spp": 1, "shard_size": 4}, "train": {"steps": 12},
                "export": {"precision": "fp32", "eval_samples": 8}, "self_test": {"frames": 2}}
COMPILE = [sys.executable, "-c", "import sys; from vc.cli.compile import main; sys.exit(main())"]
RENDER = [sys.executable, "-c", "import sys; from vc.cli.render import main; sys.exit(main())"]


#: The files of a compile that must be the same bytes whatever happened on the way (not the logs and summaries,
#: which hold timings; not the checkpoints, which hold the training time).
DETERMINISTIC = ("renders/r*/shard-*/**/*", "bundle/models/*")
SHARDS = ("r*/shard-*/**/*",)


def _digests(folder: Path, patterns: tuple[str, ...]) -> dict[str, str]:
    return {str(path.relative_to(folder)): hashlib.sha256(path.read_bytes()).hexdigest()
            for pattern in patterns for path in sorted(folder.glob(pattern)) if path.is_file()}


def _run(command: list[str], **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run(command, capture_output=True, text=True, timeout=900, **kwargs)


def _kill_when(command: list[str], reached: Callable[[], bool], then_wait: float = 0.0) -> None:
    """Start ``command``, and SIGKILL it (its whole process group) as soon as ``reached()`` holds."""
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    deadline = time.monotonic() + 900
    while not reached():
        if process.poll() is not None:
            pytest.fail(f"{command[-4:]} ended (status {process.returncode}) before the fault point: "
                        f"{process.stderr.read()}")
        assert time.monotonic() < deadline, "fault point never reached"
        time.sleep(0.02)
    time.sleep(then_wait)
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    process.stderr.close()


@pytest.fixture(scope="module")
def budget(tmp_path_factory) -> Path:
    return write_compile_config(tmp_path_factory.mktemp("budget"), FAULT_BUDGET)


@pytest.fixture(scope="module")
def straight(tmp_path_factory, budget) -> Path:
    """The compile that nothing interrupted: what every faulted one must end as."""
    output = tmp_path_factory.mktemp("straight") / "demo"
    result = _run([*COMPILE, SCENE, "-o", str(output), "--config", str(budget), "--quiet"])
    assert result.returncode == 0, result.stderr
    return output


def _stages_done(output: Path) -> list[str]:
    try:
        return list(json.loads((output / "compile.json").read_text())["stages"])
    except (FileNotFoundError, json.JSONDecodeError, KeyError):
        return []


def test_a_compile_killed_in_every_stage_resumes_to_the_same_bytes(straight, budget, tmp_path):
    output = tmp_path / "demo"
    command = [*COMPILE, SCENE, "-o", str(output), "--config", str(budget), "--quiet"]
    # 1. During the render: the first shard is finished, the next one is being written.
    _kill_when(command, lambda: (output / "renders" / "r0" / "shard-00000" / CHECKSUMS).is_file())
    # 2. During training: region r0's network is finished, r1's is training.
    _kill_when(command, lambda: checkpoint_path(output / "run", "r0").is_file())
    # 3. During the export: training is recorded as done, the bundle is being built.
    _kill_when(command, lambda: "train" in _stages_done(output), then_wait=0.5)
    assert not (output / "bundle" / "manifest.json").exists() or "export" in _stages_done(output)
    result = _run(command)
    assert result.returncode == 0, result.stderr
    assert _digests(output, DETERMINISTIC) == _digests(straight, DETERMINISTIC)
    assert _stages_done(output) == _stages_done(straight)
    assert not list(output.rglob("*.partial")) and not list(output.rglob(".*.tmp*"))


def _file_size_limited(limit_bytes: int) -> Callable[[], None]:
    """A child set-up: writes past ``limit_bytes`` fail with EFBIG, as they would with ENOSPC on a full disk."""

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))

    return limit


def test_a_full_disk_stops_the_render_in_one_line_and_keeps_finished_shards(straight, tmp_path):
    renders = tmp_path / "renders"
    command = [*RENDER, SCENE, "-o", str(renders), "--samples", "12", "--spp", "1", "--shard-size", "4", "--quiet"]
    _kill_when(command, lambda: (renders / "r0" / "shard-00000" / CHECKSUMS).is_file())
    finished = _digests(renders, ("r0/shard-00000/**/*",))
    # Room for the manifest (~20 kB), not for the next sample's image (~380 kB).
    result = _run(command, preexec_fn=_file_size_limited(200_000))
    assert result.returncode == 1, result.stderr
    errors = [line for line in result.stderr.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "Traceback" not in result.stderr, result.stderr
    assert f"cannot write {renders / 'r0' / 'shard-00001.partial' / 'images'}" in errors[0]
    assert errors[0].endswith("make room and run the same command again to resume")
    assert _digests(renders, ("r0/shard-00000/**/*",)) == finished
    assert _run(command).returncode == 0
    assert _digests(renders, SHARDS) == _digests(straight / "renders", SHARDS)


def _flip_a_byte(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x01
    path.write_bytes(bytes(data))


def test_a_damaged_shard_is_refused_by_training_and_re_made_by_the_render(straight, tmp_path):
    renders = tmp_path / "renders"
    subprocess.run(["cp", "-r", str(straight / "renders"), str(renders)], check=True)
    damaged = sorted((renders / "r1" / "shard-00001" / "images").glob("*.png"))[1]
    _flip_a_byte(damaged)
    with pytest.raises(InputError, match=f"does not match the shard's {CHECKSUMS}") as error:
        open_region(renders, "r1")
    assert error.value.path == str(damaged)
    command = [*RENDER, SCENE, "-o", str(renders), "--samples", "12", "--spp", "1", "--shard-size", "4", "--quiet"]
    result = _run(command)
    assert result.returncode == 0 and "rendering the shard again" in result.stderr, result.stderr
    assert _digests(renders, SHARDS) == _digests(straight / "renders", SHARDS)


def test_a_damaged_checkpoint_is_refused_never_used(straight, tmp_path):
    path = tmp_path / "r0.pt"
    content = torch.load(checkpoint_path(straight / "run", "r0"), weights_only=True)
    first = next(iter(content["model"]))
    weight = content["model"][first]  # channels-last where the run trained so: index it, do not view it flat
    weight[(0,) * weight.dim()] += 1e-3  # one weight changed, the stored digest kept
    torch.save(content, path)
    with pytest.raises(InputError, match="does not match its digest") as error:
        load_checkpoint(path)
    assert error.value.field == "content_sha256"
    assert load_checkpoint(checkpoint_path(straight / "run", "r0")).step == FAULT_BUDGET["train"]["steps"]
