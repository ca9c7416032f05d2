"""Which operators a bundle's graphs use, measured against the set an appliance's accelerator can be expected to
compile.

An NPU or DSP compiler takes the ONNX graph ahead of time and accepts far fewer operators than a CPU runtime. The
safe graph is a static-shape CNN: convolutions and their activations, elementwise arithmetic, concatenation, resizing,
pooling, int8 quantize and dequantize, and the input's change of layout and type. It has no shape arithmetic, no
gathers and no control flow. :data:`CONSERVATIVE_OPERATORS` is that set: this project's judgement of what such a graph
needs, not one vendor's list. A target's own list decides: Qualcomm (its ONNX converter's "Supported ONNX Ops"),
onnx-tensorrt and FuriosaAI publish theirs, and the last lacks even Resize and QuantizeLinear. ``vc-export`` reports
any operator outside the set, per region, and does not refuse the graph: a CPU or GPU appliance runs it as it is.
"""

from __future__ import annotations

from collections import Counter

import onnx

CONSERVATIVE_OPERATORS = frozenset({
    "Conv", "ConvTranspose", "Relu", "Clip", "Sigmoid",  # convolutions and their activations
    "Add", "Sub", "Mul", "Div",  # elementwise arithmetic
    "Concat", "Resize", "MaxPool", "AveragePool",  # joining, resizing, pooling
    "QuantizeLinear", "DequantizeLinear",  # int8
    "Transpose", "Cast", "Constant",  # the camera's NHWC uint8 crop to NCHW float; constants
})


def graph_operators(model: bytes) -> Counter:
    """How many nodes of each operator the ONNX ``model`` has (its main graph; the bundles' graphs have no
    subgraphs)."""
    return Counter(node.op_type for node in onnx.load_from_string(model).graph.node)


def outside_conservative_set(model: bytes) -> list[str]:
    """The operators of ``model`` outside :data:`CONSERVATIVE_OPERATORS`, sorted (empty: a graph an NPU compiler
    can be expected to take)."""
    return sorted(set(graph_operators(model)) - CONSERVATIVE_OPERATORS)
