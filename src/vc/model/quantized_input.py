"""The input of an int8 region graph: the crop's pixels quantized as they are, not normalised first.

The exported graph (:mod:`vc.model.export`) resizes the crop in float, scales it to [0, 1] and the network centres
it to [-1, 1] — a Div, a Sub and a Div over every input value — just before the int8 graph's first quantizer turns
it back into 8-bit codes for the first convolution. With that quantizer's step fixed to one pixel level
(:data:`NORMALISED_STEP` of the centred input; zero point :data:`ZERO_POINT`) the codes are the pixel values again,
so :func:`quantize_pixels_directly` replaces the three float operators and the quantizer by one quantizer of the
pixels (step 1, zero point 0) and moves what separates the two — code 128 stood for pixel 127.5, the centre; now it
stands for pixel 128 — into the first convolution's bias, where a constant input offset belongs.

Why: the three float operators cost a few percent of a region network's time, and the quantizer rounded half-way
values to even codes, so every odd pixel value reached the network as the even one above it
(docs/decisions/0004-network-architecture.md). The first convolution pads with its input zero point, real value 0,
mid-grey as in training, before and after; only at the border does the bias carry the half-level offset for taps
that fall on padding, a 1/255 difference.
"""

from __future__ import annotations

import numpy as np
import onnx
from onnx import helper, numpy_helper

from vc.model.network import INPUT_CENTRE, INPUT_HALF_RANGE

#: The crop's 8-bit levels in the centred network input ([0, 255] -> [-1, 1]): the first quantizer's step.
NORMALISED_STEP = 1.0 / (255.0 * INPUT_HALF_RANGE)
#: The first quantizer's zero point: the code of the centre, rounded up (pixel 127.5 has none).
ZERO_POINT = 128
#: The exported graph's normalisation in front of the network, operator by operator (DeployedNetwork, then
#: ScenePoseNet.forward): what :func:`quantize_pixels_directly` expects to remove.
NORMALISATION = (("Div", 255.0), ("Sub", INPUT_CENTRE), ("Div", INPUT_HALF_RANGE))


def network_input_overrides(fp32: onnx.ModelProto) -> dict[str, list[dict]]:
    """onnxruntime ``TensorQuantOverrides`` that fix the quantization of the network's normalised input to the pixel
    levels: calibrated, it would follow the calibration renders' darkest and brightest pixels, not the 8 bits."""
    return {_normalised_input(fp32): [{"scale": np.array(NORMALISED_STEP, np.float32),
                                      "zero_point": np.array(ZERO_POINT, np.uint8)}]}


def _normalised_input(graph_model: onnx.ModelProto) -> str:
    """The tensor the first convolution reads: the crop resized and normalised."""
    first_conv = next(node for node in graph_model.graph.node if node.op_type == "Conv")
    return first_conv.input[0]


def quantize_pixels_directly(int8: onnx.ModelProto) -> onnx.ModelProto:
    """``int8`` (QDQ, its first quantizer fixed by :func:`network_input_overrides`) with the normalisation removed:
    the (resized) crop is quantized at step 1 and the first convolution's bias takes the half-level offset."""
    model = onnx.ModelProto()
    model.CopyFrom(int8)
    graph = model.graph
    initialisers = {initialiser.name: initialiser for initialiser in graph.initializer}
    producer = {output: node for node in graph.node for output in node.output}
    readers: dict[str, list[onnx.NodeProto]] = {}
    for node in graph.node:
        for name in node.input:
            readers.setdefault(name, []).append(node)

    def constant(name: str) -> np.ndarray:
        return numpy_helper.to_array(initialisers[name])

    # 1. Walk back from the first quantizer over the normalisation to the pixels (the resize's or the cast's output).
    quantizer = next(node for node in graph.node if node.op_type == "QuantizeLinear"
                     and node.input[0] not in initialisers)
    normalisation, tensor = [], quantizer.input[0]
    for op_type, value in reversed(NORMALISATION):
        node = producer.get(tensor)
        if node is None or node.op_type != op_type or not np.isclose(constant(node.input[1]), value):
            raise ValueError(f"expected the exported normalisation {NORMALISATION} before the first quantizer, found "
                             f"{node.op_type if node else 'the graph input'} producing {tensor!r}")
        normalisation.append(node)
        tensor = node.input[0]
    step, zero_point = float(constant(quantizer.input[1])), int(constant(quantizer.input[2]))
    if not np.isclose(step, NORMALISED_STEP, rtol=1e-6) or zero_point != ZERO_POINT:
        raise ValueError(f"the first quantizer's step {step} / zero point {zero_point} are not the pixel levels "
                         f"({NORMALISED_STEP} / {ZERO_POINT}): quantize with network_input_overrides")

    # 2. The first convolution reads that quantizer's codes (through a DequantizeLinear): its bias takes the offset.
    (dequantizer,) = readers[quantizer.output[0]]
    (convolution,) = readers[dequantizer.output[0]]
    weight_codes, weight_steps = (constant(name) for name in producer[convolution.input[1]].input[:2])
    weights = weight_codes.astype(np.float64) * np.asarray(weight_steps, np.float64).reshape(-1, 1, 1, 1)
    bias_node = producer[convolution.input[2]]
    bias_codes, bias_steps = constant(bias_node.input[0]), np.asarray(constant(bias_node.input[1]), np.float64)
    offset = (ZERO_POINT - 127.5) * NORMALISED_STEP  # the centred value of a pixel minus what its code now stands for
    shifted = bias_codes + np.round(offset * weights.sum(axis=(1, 2, 3)) / bias_steps).astype(bias_codes.dtype)
    initialisers[bias_node.input[0]].CopyFrom(numpy_helper.from_array(shifted, bias_node.input[0]))

    # 3. One quantizer of the pixels, step 1 and zero point 0, in place of the normalisation and the old quantizer.
    graph.initializer.extend([numpy_helper.from_array(np.array(1.0, np.float32), "pixel_step"),
                              numpy_helper.from_array(np.array(0, np.uint8), "pixel_zero_point")])
    pixels = helper.make_node("QuantizeLinear", [tensor, "pixel_step", "pixel_zero_point"], [quantizer.output[0]],
                              name="pixels_quantized")
    removed = {id(node) for node in [*normalisation, quantizer]}
    nodes = [node for node in graph.node if id(node) not in removed]
    nodes.insert(nodes.index(producer[tensor]) + 1, pixels)
    del graph.node[:]
    graph.node.extend(nodes)
    used = {name for node in nodes for name in node.input}
    for name in [node.input[1] for node in normalisation] + list(quantizer.input[1:]):
        if name not in used and name in initialisers:
            graph.initializer.remove(initialisers.pop(name))
    onnx.checker.check_model(model)
    return model
