"""examples/c/run_region.c, built against the OpenVINO wheel's C API and the C decoder, run on a frame of the test
bundle: the people it prints are those the Python runtime finds in that region on the same engine."""

from __future__ import annotations

import importlib.util
import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from dataset_factory import region_camera, sample

from vc.deploy import native
from vc.deploy.bundle import load_bundle, sha256
from vc.deploy.decoder_file import DECODER_FILE, decoder_file
from vc.deploy.runtime import Runtime

REPO = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _openvino() -> Path:
    spec = importlib.util.find_spec("openvino")
    if spec is None or not native.available():
        pytest.skip("needs the openvino package (the dev install has it) and the built C decoder")
    root = Path(spec.submodule_search_locations[0])
    if not (root / "include" / "openvino" / "c" / "openvino.h").is_file():
        pytest.skip(f"this openvino wheel ships no C headers ({root / 'include'})")
    return root


def _write_ppm(path: Path, image: np.ndarray) -> None:
    height, width, _ = image.shape
    path.write_bytes(f"P6 {width} {height} 255\n".encode() + np.ascontiguousarray(image, np.uint8).tobytes())


@pytest.fixture(scope="module")
def example(tmp_path_factory) -> Path:
    openvino = _openvino()
    library = sorted((openvino / "libs").glob("libopenvino_c.so*"))[0]
    program = tmp_path_factory.mktemp("c_example") / "run_region"
    subprocess.run(["cc", "-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-I", str(native.SOURCES),
                    "-I", str(openvino / "include"), str(REPO / "examples" / "c" / "run_region.c"),
                    str(native.SOURCES / "vc_decode.c"), str(native.SOURCES / "vc_bundle.c"), str(library),
                    f"-Wl,-rpath,{library.parent}", "-lm", "-o", str(program)], check=True)
    return program


def test_the_c_example_finds_the_people_the_python_runtime_finds(example, bundle, tmp_path):
    frame = sample(region_camera(), 0).image
    # The test bundle's two-step network finds no one at the shipped threshold: lowered under its strongest peak.
    copy = Path(shutil.copytree(bundle, tmp_path / "bundle"))
    with Runtime(bundle, threads=1) as runtime:
        strongest = float(runtime.runners[0].heatmaps(frame)[0].max())
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["regions"][0]["decode"]["centre_threshold"] = 0.9 * strongest
    files = {region["expected_height"]: (copy / region["expected_height"]).read_bytes()
             for region in manifest["regions"]}
    (copy / DECODER_FILE).write_bytes(decoder_file(manifest, files))
    manifest["decoder_file_sha256"] = sha256((copy / DECODER_FILE).read_bytes())
    (copy / "manifest.json").write_text(json.dumps(manifest))
    _write_ppm(tmp_path / "frame.ppm", frame)
    region = load_bundle(copy).regions[0]
    printed = subprocess.run([str(example), str(copy / DECODER_FILE), region.name, str(copy / "models" /
                              f"{region.name}.onnx"), str(tmp_path / "frame.ppm")], capture_output=True, text=True,
                             check=True).stdout.splitlines()
    with Runtime(copy, threads=1, engine="openvino", decoder="c") as runtime:
        runner = runtime.runners[0]
        people = native.decode(runner.heatmaps(frame), region.decode, region.expected_height_px)
        expected = [[person.score, *runner.to_frame(person.box.reshape(2, 2)).ravel(),
                     *np.column_stack([runner.to_frame(person.keypoints[:, :2]), person.keypoints[:, 2]]).ravel()]
                    for person in people]
    assert len(printed) == len(expected) > 0
    np.testing.assert_allclose(np.array([[float(value) for value in line.split()[:56]] for line in printed]),
                               np.array(expected), rtol=0, atol=1e-3)


def test_the_c_example_refuses_a_frame_of_another_size(example, bundle, tmp_path):
    _write_ppm(tmp_path / "small.ppm", np.zeros((4, 4, 3), np.uint8))
    region = load_bundle(bundle).regions[0].name
    result = subprocess.run([str(example), str(bundle / DECODER_FILE), region, str(bundle / "models" /
                             f"{region}.onnx"), str(tmp_path / "small.ppm")], capture_output=True, text=True)
    assert result.returncode == 2 and "not a binary PPM of the bundle's camera's size" in result.stderr
