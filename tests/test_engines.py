"""A bundle's graphs on a second engine (OpenVINO) and against the operators an NPU compiler takes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from dataset_factory import region_camera, sample

from vc.cli.export import main as vc_export
from vc.cli.run import main as vc_run
from vc.deploy.runtime import Runtime
from vc.errors import InputError
from vc.io import write_image
from vc.model.operators import CONSERVATIVE_OPERATORS, outside_conservative_set

pytest.importorskip("openvino", reason="openvino is a dev dependency (the openvino extra): make install")


@pytest.fixture(scope="module")
def int8_bundle(trained_run, tmp_path_factory) -> Path:
    output = tmp_path_factory.mktemp("int8") / "bundle"
    assert vc_export([str(trained_run), "-o", str(output), "--precision", "int8", "--eval-samples", "0",
                      "--calibration-samples", "4", "--quiet"]) == 0
    return output


@pytest.fixture(scope="module")
def talkative_bundle(bundle, tmp_path_factory) -> Path:
    """The fp32 test bundle decoding people from its two-step network's faint centre peaks: its centre threshold
    lowered under the strongest peak of the first test frame (as shipped it finds no one)."""
    copy = Path(shutil.copytree(bundle, tmp_path_factory.mktemp("talkative") / "bundle"))
    with Runtime(bundle, threads=1) as runtime:
        strongest = float(runtime.runners[0].heatmaps(sample(region_camera(), 0).image)[0].max())
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["regions"][0]["decode"]["centre_threshold"] = 0.9 * strongest
    (copy / "manifest.json").write_text(json.dumps(manifest))
    return copy


def _frames() -> list[np.ndarray]:
    """The test camera's frames with people in them, and hostile ones: black, white, noise."""
    noise = np.random.default_rng(0).integers(0, 256, sample(region_camera(), 0).image.shape, dtype=np.uint8)
    return [sample(region_camera(), index).image for index in range(6)] + [
        np.zeros_like(noise), np.full_like(noise, 255), noise]


def test_an_fp32_bundle_gives_the_same_heat_maps_and_people_on_both_engines(talkative_bundle):
    people = 0
    with Runtime(talkative_bundle, threads=1) as ours, \
            Runtime(talkative_bundle, threads=1, engine="openvino") as theirs:
        for frame in _frames():
            np.testing.assert_allclose(theirs.runners[0].heatmaps(frame), ours.runners[0].heatmaps(frame),
                                       atol=1e-4, rtol=0)
        # the people on the frames with people: on the hostile ones this network's peaks sit at its lowered
        # threshold, where float rounding decides
        for frame in _frames()[:6]:
            expected, found = ours(frame), theirs(frame)
            assert len(found) == len(expected)
            people += len(found)
            # a two-step network's maps are nearly flat, so float rounding moves a sub-pixel peak by up to 0.01 px
            # (a compiled PETS09 bundle's by 3e-5: experiments/2026-11-30-openvino-parity/)
            for a, b in zip(expected, found, strict=True):
                np.testing.assert_allclose(b.box, a.box, atol=0.05)
                np.testing.assert_allclose(b.keypoints, a.keypoints, atol=0.05)
    assert people > 0


def test_an_int8_bundle_runs_on_openvino_within_a_quantization_step(int8_bundle):
    """OpenVINO's CPU plugin rounds int8 its own way (vc.deploy.engines): the heat maps agree to about one step of
    the output's quantization, not to float rounding."""
    with Runtime(int8_bundle, threads=1) as ours, Runtime(int8_bundle, threads=1, engine="openvino") as theirs:
        for frame in _frames():
            expected, found = ours.runners[0].heatmaps(frame), theirs.runners[0].heatmaps(frame)
            assert found.shape == expected.shape and np.isfinite(found).all()
            assert np.abs(found - expected).max() <= 0.1 * max(np.abs(expected).max(), 1e-3) + 0.02


def test_an_unknown_engine_is_refused_by_name(bundle, tmp_path, capsys):
    with pytest.raises(InputError, match="engine"):
        Runtime(bundle, engine="tensorrt")
    write_image(tmp_path / "frames" / "a.png", sample(region_camera(), 0).image)
    with pytest.raises(SystemExit) as refused:
        vc_run([str(bundle), str(tmp_path / "frames"), "-o", str(tmp_path / "out"), "--engine", "tensorrt"])
    assert refused.value.code == 2 and "--engine" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_vc_run_on_openvino_says_so_and_finds_what_onnxruntime_finds(talkative_bundle, tmp_path):
    frames = tmp_path / "frames"
    for index in range(3):
        write_image(frames / f"{index}.png", sample(region_camera(), index).image)
    runs = {}
    for engine in ("onnxruntime", "openvino"):
        assert vc_run([str(talkative_bundle), str(frames), "-o", str(tmp_path / engine), "--engine", engine,
                       "--quiet"]) == 0
        assert json.loads((tmp_path / engine / "summary.json").read_text())["engine"] == engine
        runs[engine] = [[person["box"] for person in json.loads(line)["people"]]
                        for line in (tmp_path / engine / "detections.jsonl").read_text().splitlines()]
    assert [len(boxes) for boxes in runs["openvino"]] == [len(boxes) for boxes in runs["onnxruntime"]]
    assert sum(len(boxes) for boxes in runs["onnxruntime"]) > 0
    np.testing.assert_allclose(np.array(sum(runs["openvino"], []), float).reshape(-1, 4),
                               np.array(sum(runs["onnxruntime"], []), float).reshape(-1, 4), atol=0.05)


def test_the_export_reports_each_graphs_operators_against_the_conservative_set(bundle, int8_bundle):
    for path in (bundle, int8_bundle):
        for region in json.loads((path / "manifest.json").read_text())["regions"]:
            model = (path / region["model"]).read_bytes()
            assert region["operators_outside_conservative_set"] == outside_conservative_set(model)
            assert set(region["operators"]) - CONSERVATIVE_OPERATORS == set(outside_conservative_set(model))
            assert "Conv" in region["operators"]
            # the fixed shapes folded at export (vc.model.export.folded): nothing an NPU compiler would refuse
            assert region["operators_outside_conservative_set"] == [] and "Shape" not in region["operators"]


def test_an_operator_outside_the_set_is_named():
    import onnx
    from onnx import TensorProto, helper

    graph = helper.make_graph([helper.make_node("Shape", ["x"], ["s"]), helper.make_node("Relu", ["x"], ["y"])],
                              "g", [helper.make_tensor_value_info("x", TensorProto.FLOAT, [1, 3])],
                              [helper.make_tensor_value_info("y", TensorProto.FLOAT, [1, 3]),
                               helper.make_tensor_value_info("s", TensorProto.INT64, [2])])
    model = helper.make_model(graph).SerializeToString()
    assert outside_conservative_set(model) == ["Shape"]
    assert onnx.load_from_string(model).graph.node[1].op_type in CONSERVATIVE_OPERATORS


def test_a_bundle_whose_graph_sees_markers_finds_each_marker_once_on_openvino(bundle, tmp_path):
    """A graph built by hand (tests/serve_factory.py: a person at each white cell) runs on OpenVINO as on
    onnxruntime: a vendor runtime reads the bundle's graphs, not only the exporter's."""
    from serve_factory import marker_bundle, marker_frame

    markers = marker_bundle(bundle, tmp_path / "markers")
    frame = marker_frame((128, 64), [(5, 8), (20, 8)])
    with Runtime(markers, threads=1) as ours, Runtime(markers, threads=1, engine="openvino") as theirs:
        expected, found = ours(frame), theirs(frame)
    assert len(found) == len(expected) == 2
    for a, b in zip(expected, found, strict=True):
        np.testing.assert_allclose(b.box, a.box, atol=1e-3)


def test_vc_eval_on_openvino_scores_as_on_onnxruntime(talkative_bundle, tmp_path):
    from test_eval import _video_and_truth

    from vc.cli.eval import main as vc_eval

    video, truth = _video_and_truth(tmp_path)
    metrics = {}
    for engine in ("onnxruntime", "openvino"):
        assert vc_eval([str(talkative_bundle), "--video", str(video), "--gt", str(truth), "-o", str(tmp_path / engine),
                        "--threads", "1", "--no-hog", "--engine", engine, "--quiet"]) == 0
        metrics[engine] = json.loads((tmp_path / engine / "metrics.json").read_text())
        assert metrics[engine]["engine"] == engine
    ap50 = {engine: {name: detector["ap50"] for name, detector in found["detectors"].items()}
            for engine, found in metrics.items()}
    assert ap50["openvino"] == pytest.approx(ap50["onnxruntime"], abs=1e-6)

