"""Scenes at the edge of what a camera can be: each is planned (vc-scene check: regions whose people are in
range) or refused with one clear line, never a traceback."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import write_compile_config
from scene_factory import base_scene, write_scene

from vc.calibration.camera import look_at
from vc.cli.scene import main as vc_scene


def _looking(eye, target, focal: float = 300.0, distortion: dict | None = None) -> dict:
    scene = base_scene()
    rotation, translation = look_at(eye, target)
    scene["camera"].update(R=rotation.tolist(), t=translation.tolist(),
                           K=[[focal, 0.0, 159.5], [0.0, focal, 119.5], [0.0, 0.0, 1.0]],
                           distortion=distortion or {"model": "none"})
    return scene


PLANNED = {
    "strong wide-angle distortion (Town Centre-like k1, k2)": _looking(
        [0.0, -12.0, 6.0], [0.0, 8.0, 0.0], distortion={"model": "opencv", "k": [-0.6, 4.7, 0.0, 0.0, 0.0]}),
    "near-horizontal camera, horizon across the walkable area": _looking([0.0, -12.0, 1.6], [0.0, 20.0, 1.4]),
    "top-down camera": _looking([0.0, 6.0, 12.0], [0.0, 6.01, 0.0]),
    "tiny people (16-25 px, a short lens)": _looking([0.0, -14.0, 6.0], [0.0, 8.0, 0.0], focal=150.0),
    "huge people (close, long lens)": _looking([0.0, -6.0, 2.0], [0.0, 0.0, 0.8], focal=400.0),
}
PLANNED["walkable area mostly out of view"] = {**base_scene(), "layout": {
    **base_scene()["layout"], "walkable": [[[-200.0, -200.0], [200.0, -200.0], [200.0, 200.0], [-200.0, 200.0]]]}}
PLANNED["part of the ground behind a wall taller than anyone"] = {**base_scene(), "layout": {
    **base_scene()["layout"], "walls": [{"start": [-8.0, 6.0], "end": [8.0, 6.0], "height": 4.0}]}}
PLANNED["a crowded region (everyone in groups on 4 m x 4 m)"] = {**base_scene(), "priors": {"group_rate": 1.0},
                                                                  "layout": {**base_scene()["layout"], "walkable": [
                                                                      [[-2.0, 4.0], [2.0, 4.0], [2.0, 8.0],
                                                                       [-2.0, 8.0]]]}}
REFUSED = {
    "a camera looking at the sky": (_looking([0.0, -12.0, 2.0], [0.0, 10.0, 12.0]), "no walkable area is in view"),
    "people taller than the image everywhere (a long lens close by)": (
        _looking([0.0, -5.0, 1.0], [0.0, 5.0, 0.5], focal=3000.0), "taller than the image or cannot be seen whole"),
    "people under 16 px everywhere (a camera far off)": (
        _looking([0.0, -60.0, 10.0], [0.0, 8.0, 0.0], focal=150.0), "where people are >= 16 px tall"),
}


@pytest.mark.parametrize("case", list(PLANNED))
def test_edge_cameras_are_planned_with_people_in_range(tmp_path, capsys, case):
    path = write_scene(tmp_path, PLANNED[case])
    assert vc_scene(["check", str(path), "--json", str(tmp_path / "summary.json")]) == 0, capsys.readouterr().err
    regions = json.loads((tmp_path / "summary.json").read_text())["regions"]
    assert regions
    for region in regions:
        low, high = region["person_height_px"]
        assert np.isfinite([low, high]).all() and 0 < low <= high


@pytest.mark.parametrize("case", list(REFUSED))
def test_impossible_cameras_are_refused_in_one_line(tmp_path, capsys, case):
    scene, message = REFUSED[case]
    assert vc_scene(["check", str(write_scene(tmp_path, scene))]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and message in error


#: The least that runs every stage: two shards per region (training holds one out), one step, one test frame.
TOY = {"render": {"samples": 4, "spp": 1, "shard_size": 2}, "train": {"steps": 1, "batch_size": 2},
       "export": {"precision": "fp32", "eval_samples": 0}, "self_test": {"frames": 1}}


@pytest.mark.slow
@pytest.mark.xdist_group("anny")
@pytest.mark.parametrize("case", list(PLANNED))
def test_edge_cameras_compile_to_a_bundle_with_finite_labels_and_outputs(tmp_path, capsys, case):
    """Each planned edge scene goes through every stage: renders whose labels are finite, a bundle whose regions
    are the planned ones, and a self-test whose numbers are finite (the network is untrained: what matters here
    is that nothing non-finite reaches a label, a checkpoint or an output, not the accuracy)."""
    from vc.cli.compile import main as vc_compile
    from vc.model.trainer import checkpoint_path, load_checkpoint

    scene = write_scene(tmp_path / "scene", PLANNED[case])
    config = write_compile_config(tmp_path, TOY)
    output = tmp_path / "out"
    assert vc_compile([str(scene), "-o", str(output), "--config", str(config), "--quiet"]) == 0, \
        capsys.readouterr().err
    state = json.loads((output / "compile.json").read_text())
    planned = [region["name"] for region in state["stages"]["check"]["regions"]]
    bundle = json.loads((output / "bundle" / "manifest.json").read_text())
    assert [region["name"] for region in bundle["regions"]] == planned
    for shard_labels in output.glob("renders/*/shard-*/annotations.json"):
        for person in json.loads(shard_labels.read_text())["annotations"]:
            numbers = [*person["keypoints"], *person["bbox"], *person["amodal_bbox"], *(person["center"] or [])]
            assert np.isfinite(numbers).all(), shard_labels
    for name in planned:
        weights = load_checkpoint(checkpoint_path(output / "run", name)).content["model"]
        assert all(bool(tensor.isfinite().all()) for tensor in weights.values() if tensor.is_floating_point())
    self_test = state["stages"]["self-test"]
    assert np.isfinite([self_test["ap50"], self_test["ms_per_frame"]]).all()
