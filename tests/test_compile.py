"""vc-compile end to end on the demo scene at a toy budget: every stage runs once, a second run skips them all, the
config it wrote compiles the same bytes again, and the self-test's composed frames carry their people's boxes."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import write_compile_config

from vc.cli import compile as compile_cli
from vc.cli import train as train_cli
from vc.evaluation.selftest import composite_frame
from vc.io import read_image
from vc.render.dataset import open_region
from vc.stages.config import CONFIG_FILE, PRESETS, CompileConfig, read_config

DEMO = "examples/scenes/demo/scene.yaml"

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("anny")]
TOY = {"render": {"samples": 20, "spp": 1, "shard_size": 10}, "train": {"steps": 2},
       "export": {"precision": "auto", "eval_samples": 10}, "self_test": {"frames": 2}}


@pytest.fixture(scope="module")
def toy_config(tmp_path_factory) -> Path:
    return write_compile_config(tmp_path_factory.mktemp("config"), TOY)


@pytest.fixture(scope="module")
def compiled(tmp_path_factory, toy_config) -> tuple:
    output = tmp_path_factory.mktemp("compile") / "demo"
    code = compile_cli.main([DEMO, "-o", str(output), "--config", str(toy_config), "--quiet"])
    return code, output


def _digests(folder: Path, pattern: str) -> dict[str, str]:
    return {str(path.relative_to(folder)): hashlib.sha256(path.read_bytes()).hexdigest()
            for path in sorted(folder.rglob(pattern)) if path.is_file()}


def test_every_stage_runs_and_is_recorded(compiled):
    code, output = compiled
    assert code == 0
    state = json.loads((output / "compile.json").read_text())
    assert list(state["stages"]) == ["check", "render", "train", "export", "self-test"]
    assert state["stages"]["self-test"]["frames"] == 2 and state["stages"]["self-test"]["people_asked_for"] > 0
    assert set(state["stages"]["export"]["precision"]) == {"r0", "r1"}
    for accuracy in state["stages"]["train"]["held_out"].values():  # what the summary prints, groups included
        assert set(accuracy) == {"ap50", "pckh", "mask_iou", "recall_overlapping"}
    for path in ("bundle/manifest.json", "run/metrics.json", "overlay.png", "test_frame.png"):
        assert (output / path).is_file()
    frame, overlay = read_image(output / "test_frame.png"), read_image(output / "overlay.png")
    assert frame.shape == overlay.shape and not np.array_equal(frame, overlay)  # the overlay is that frame, drawn on


def test_a_second_run_skips_finished_stages(compiled, capsys):
    _, output = compiled
    before = (output / "bundle" / "manifest.json").stat().st_mtime_ns
    assert compile_cli.main([DEMO, "-o", str(output), "--config", str(output / CONFIG_FILE),
                             "--quiet"]) == 0
    assert capsys.readouterr().out.count("done before") == 5
    assert (output / "bundle" / "manifest.json").stat().st_mtime_ns == before


def test_the_written_config_compiles_the_same_bytes(compiled, tmp_path):
    """The config a compile writes beside its outputs is the whole of what it depends on besides the scene: read back
    with --config into a new folder, it renders byte-identical shards and exports the same models."""
    _, output = compiled
    assert read_config(output / CONFIG_FILE) == CompileConfig.model_validate(TOY)
    again = tmp_path / "again"
    assert compile_cli.main([DEMO, "-o", str(again), "--config", str(output / CONFIG_FILE),
                             "--quiet"]) == 0
    renders = _digests(output / "renders", "shard-*/*")
    assert renders and renders == _digests(again / "renders", "shard-*/*")
    models = {region["name"]: region["model_sha256"] for region in
              json.loads((output / "bundle" / "manifest.json").read_text())["regions"]}
    assert models == {region["name"]: region["model_sha256"] for region in
                      json.loads((again / "bundle" / "manifest.json").read_text())["regions"]}


def test_a_budget_is_a_preset_and_set_changes_one_field():
    parser = compile_cli._parser()
    quick = compile_cli.config_from(parser.parse_args(["s.yaml", "-o", "o", "--budget", "quick"]))
    assert quick == PRESETS["quick"]
    changed = compile_cli.config_from(parser.parse_args(["s.yaml", "-o", "o", "--budget", "quick", "--set",
                                                         "train.steps=7", "--seed", "3"]))
    assert (changed.train.steps, changed.render.seed, changed.train.seed) == (7, 3, 3)
    assert changed.render.samples == quick.render.samples and changed.export == quick.export
    assert compile_cli.config_from(parser.parse_args(["s.yaml", "-o", "o"])) == PRESETS["standard"]


def test_a_compile_choosing_its_precision_without_held_out_renders_is_refused_naming_the_field(tmp_path, capsys):
    # the default budgets choose the precision on held-out renders (auto): none to measure on is bad input
    output = tmp_path / "out"
    assert compile_cli.main(["s.yaml", "-o", str(output), "--set", "export.eval_samples=0"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "export.eval_samples" in error and "precision auto" in error
    assert not output.exists()


@pytest.mark.parametrize(("assignment", "field", "reason"),
                         [("render.samples=100", "render", "one shard a region"),
                          ("train.width=15", "train.width", "divide width 15")])
def test_a_compile_that_would_fail_after_rendering_is_refused_before_it(tmp_path, capsys, assignment, field, reason):
    # one shard a region, or a width the network cannot take, used to be found by training, after the renders
    output = tmp_path / "out"
    assert compile_cli.main(["s.yaml", "-o", str(output), "--set", assignment]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and f"--set {field}:" in error and reason in error
    assert not output.exists()


def test_the_offsets_weight_reaches_the_loss_and_only_with_the_offsets():
    from vc.stages.config import TrainSettings
    weighed = TrainSettings(centre_offsets=True, centre_offset_weight=0.3, centre_sigma=0.05).train_config()
    assert weighed.loss.centre_offsets == 0.3 and weighed.codec.centre_offsets
    assert weighed.loss.detection > TrainSettings().train_config().loss.detection  # the sharper map's weight kept
    assert TrainSettings(centre_offsets=True, centre_offset_weight=1.0).train_config().loss.centre_offsets == 1.0


def test_an_offsets_weight_without_the_offsets_is_one_line_naming_the_field(tmp_path, capsys):
    renders = tmp_path / "renders"
    renders.mkdir()
    assert train_cli.main([str(renders), "-o", str(tmp_path / "run"), "--offset-weight", "0.3"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "centre_offset_weight" in error and "centre_offsets" in error
    assert not (tmp_path / "run").exists()


def test_a_fine_centre_map_without_the_offsets_is_one_line_naming_the_field(tmp_path, capsys):
    from vc.stages.config import TrainSettings
    assert TrainSettings(centre_offsets=True, fine_centre=True).train_config().codec.fine_centre
    renders = tmp_path / "renders"
    renders.mkdir()
    assert train_cli.main([str(renders), "-o", str(tmp_path / "run"), "--fine-centre"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "fine_centre" in error and "centre_offsets" in error
    assert not (tmp_path / "run").exists()


def test_a_bad_config_file_is_one_line_naming_the_field(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({**TOY, "train": {"steps": -1}}))
    assert compile_cli.main([DEMO, "-o", str(tmp_path / "out"), "--config", str(bad)]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and str(bad) in error and "train.steps" in error
    assert not (tmp_path / "out").exists()


def test_composed_frames_put_people_where_their_boxes_say(compiled):
    _, output = compiled
    from vc.io import read_image
    from vc.scenes.loader import load_scene

    background = read_image(load_scene(DEMO).image_path)
    regions = [open_region(output / "renders", name) for name in ("r0", "r1")]
    frame = composite_frame(background, regions, 0)
    changed = np.abs(frame.image.astype(int) - background).max(axis=2) > 0
    assert len(frame.truth_boxes) > 0
    for box, ignored in zip(frame.truth_boxes, frame.truth_ignore, strict=True):
        if ignored:
            continue
        x0, y0, x1, y1 = np.round(box).astype(int)
        inside = changed[max(y0, 0):y1, max(x0, 0):x1]
        assert inside.mean() > 0.1  # the person's pixels are in their box


def test_bring_your_own_camera_from_a_video_and_four_points(compiled, toy_config, tmp_path):
    """The README's walkthrough with measured ground points: a video and four points -> a scene -> a bundle -> an
    overlay video. The "camera" is the demo scene's, its video the demo's renders composed into its background (six
    frames: too few walkers to solve it from them; that path is tests/test_people_calibration.py's)."""
    import cv2

    from vc.cli import run as run_cli
    from vc.cli import scene as scene_cli
    from vc.io import read_image
    from vc.scenes.loader import load_scene

    _, output = compiled
    demo = load_scene(DEMO)
    regions = [open_region(output / "renders", name) for name in ("r0", "r1")]
    background = read_image(demo.image_path)
    writer = cv2.VideoWriter(str(tmp_path / "camera.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 5, demo.camera.size)
    for index in range(6):
        writer.write(np.ascontiguousarray(composite_frame(background, regions, index).image[:, :, ::-1]))
    writer.release()
    # Four points "measured with a tape": corners of the demo's walkable ground and their pixels.
    ground = np.array(demo.layout.walkable[0][:4], float)
    pixels = demo.camera.project(np.c_[ground, np.zeros(4)]).uv
    (tmp_path / "points.csv").write_text("u,v,x,y\n" + "".join(
        f"{u:.1f},{v:.1f},{x},{y}\n" for (u, v), (x, y) in zip(pixels, ground, strict=True)))

    assert scene_cli.main(["init", str(tmp_path / "camera.avi"), "-o", str(tmp_path / "camera"), "--points",
                           str(tmp_path / "points.csv")]) == 0
    # The walkthrough's commands at the toy budget: the walkthrough is under test, not the accuracy (its quick
    # budget took 14 of the suite's 20 minutes).
    assert compile_cli.main([str(tmp_path / "camera" / "scene.yaml"), "-o", str(tmp_path / "compiled"),
                             "--config", str(toy_config), "--quiet"]) == 0
    assert run_cli.main([str(tmp_path / "compiled" / "bundle"), str(tmp_path / "camera.avi"), "-o",
                         str(tmp_path / "run"), "--overlay", "--quiet"]) == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["frames"] == 6 and (tmp_path / "run" / "overlay.mp4").stat().st_size > 0


def _processes_running(task_name: str) -> list[int]:
    """Pids whose title names ``task_name`` (Ray titles a worker ``ray::<function>`` while it runs one)."""
    pids = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and f"ray::{task_name}" in (entry / "cmdline").read_bytes().decode(errors="ignore"):
                pids.append(int(entry.name))
        except OSError:
            continue
    return pids


def test_worker_processes_render_the_same_dataset(compiled, toy_config, tmp_path):
    """Two spawned worker processes of this machine render the demo's shards at the toy budget: the dataset is
    byte for byte the in-process compile's (shards are pure functions of the scene, region, index and seed)."""
    from vc.stages.executors import LocalProcesses
    from vc.stages.render import prepare_render

    _, reference = compiled
    job = prepare_render(Path(DEMO), read_config(toy_config).render)
    summary = job.run(tmp_path / "renders", show_progress=False, executor=LocalProcesses(2))
    assert summary["executor"] == "processes"
    assert _digests(tmp_path / "renders", "shard-*/*") == _digests(reference / "renders", "shard-*/*")


def test_a_ray_cluster_compiles_the_same_dataset_though_a_worker_dies_mid_shard(compiled, toy_config, tmp_path):
    """A local Ray cluster of two worker processes compiles the demo at the toy budget while a worker rendering
    a shard is killed (SIGKILL, once its shard is half-written): Ray re-runs the shard, and the dataset is byte for
    byte the in-process compile's."""
    pytest.importorskip("ray", reason="the ray extra is not installed")
    import os
    import signal
    import threading
    import time

    from vc.stages.compile import compile_scene
    from vc.stages.executors import RayExecutor

    _, reference = compiled
    output = tmp_path / "on-ray"
    executor = RayExecutor(local_cpus=2)
    try:
        record: dict = {}
        worker = threading.Thread(target=lambda: record.update(compile_scene(
            Path(DEMO), output, read_config(toy_config), show_progress=False, executor=executor)))
        worker.start()
        killed, deadline = [], time.monotonic() + 600
        while not killed and worker.is_alive() and time.monotonic() < deadline:
            if any((output / "renders").glob("r*/shard-*.partial")):
                for pid in _processes_running("render_shard"):
                    os.kill(pid, signal.SIGKILL)
                    killed.append(pid)
            time.sleep(0.02)
        worker.join(timeout=900)
    finally:
        executor.shutdown()
    assert killed, "no worker was caught mid-shard"
    assert list(record["stages"]) == ["check", "render", "train", "export", "self-test"]
    assert _digests(output / "renders", "shard-*/*") == _digests(reference / "renders", "shard-*/*")
    assert not list((output / "renders").rglob("*.partial"))
    assert set(record["stages"]["train"]["held_out"]) == {"r0", "r1"}
