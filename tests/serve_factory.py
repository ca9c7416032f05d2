"""A bundle that sees "people" where a test draws them, and the frames to show it: for the service's tests, which
need people whose number, place and motion the test chooses (a trained network finds what it finds).

:func:`marker_bundle` copies the test bundle (tests/conftest.py) and replaces its network by a hand-built ONNX graph:
the centre map is the frame's red channel averaged over each heat-map cell, every other map zero. A white square
of one cell (:data:`CELL` pixels, aligned to the cells) is then one centre peak of 1: one person, whose box the
decoder sizes from the bundle's camera. Frames are black with such squares (:func:`marker_frame`).
"""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import numpy as np
import onnx
from onnx import TensorProto, helper

CELL = 4  # the heat maps' stride


def _marker_model(width: int, height: int, channels: int) -> bytes:
    rows, columns = height // CELL, width // CELL
    zeros = helper.make_tensor("zeros", TensorProto.FLOAT, [1, channels - 1, rows, columns],
                               np.zeros((channels - 1) * rows * columns, np.float32))
    nodes = [
        helper.make_node("Cast", ["crop"], ["pixels"], to=TensorProto.FLOAT),
        helper.make_node("Transpose", ["pixels"], ["planes"], perm=[0, 3, 1, 2]),
        helper.make_node("Slice", ["planes", "start", "end", "axis"], ["red"]),
        helper.make_node("AveragePool", ["red"], ["pooled"], kernel_shape=[CELL, CELL], strides=[CELL, CELL]),
        helper.make_node("Mul", ["pooled", "scale"], ["centre"]),
        helper.make_node("Concat", ["centre", "zeros"], ["heatmaps"], axis=1),
    ]
    constants = [helper.make_tensor("start", TensorProto.INT64, [1], [0]),
                 helper.make_tensor("end", TensorProto.INT64, [1], [1]),
                 helper.make_tensor("axis", TensorProto.INT64, [1], [1]),
                 helper.make_tensor("scale", TensorProto.FLOAT, [], [1 / 255]), zeros]
    graph = helper.make_graph(
        nodes, "markers", [helper.make_tensor_value_info("crop", TensorProto.UINT8, [1, height, width, 3])],
        [helper.make_tensor_value_info("heatmaps", TensorProto.FLOAT, [1, channels, rows, columns])], constants)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)])
    model.ir_version = 8
    onnx.checker.check_model(model)
    return model.SerializeToString()


def marker_bundle(bundle: Path, output: Path, zones: list[dict] | None = None) -> Path:
    """A copy of ``bundle`` (one region covering the frame) seeing markers, with ``zones`` in its manifest."""
    output = Path(shutil.copytree(bundle, output))
    manifest = json.loads((output / "manifest.json").read_text())
    region = manifest["regions"][0]
    width, height = region["input_size"]
    model = _marker_model(width, height, len(manifest["output"]["channels"]))
    (output / region["model"]).write_bytes(model)
    region["model_sha256"] = hashlib.sha256(model).hexdigest()
    if zones is not None:
        manifest["zones"] = zones
    (output / "manifest.json").write_text(json.dumps(manifest, indent=2) + "\n")
    return output


def marker_frame(size: tuple[int, int], cells: list[tuple[int, int]]) -> np.ndarray:
    """A black RGB frame of ``size`` (width, height) with a white square on each heat-map cell (column, row)."""
    width, height = size
    frame = np.zeros((height, width, 3), np.uint8)
    for column, row in cells:
        frame[row * CELL:(row + 1) * CELL, column * CELL:(column + 1) * CELL] = 255
    return frame
