"""The inference engines a region's graph runs on: the same ONNX bytes, two vendors' runtimes.

``onnxruntime`` is the runtime's own, and the engine an appliance with onnxruntime's C API runs. ``openvino`` (pip
``openvino``, its CPU plugin) is a second vendor's. It is what Intel CPUs, GPUs and NPUs run, and it checks that a
bundle does not depend on one runtime's reading of its graphs. Both take the region's crop as the camera gives it
((1, H, W, 3) uint8) and return its heat maps ((1, C, h, w) float32).

An fp32 graph gives the same heat maps on both to float rounding. An int8 graph does not: OpenVINO's CPU plugin
fuses each quantize-dequantize pair into integer kernels and rounds its own way, so a heat map differs by about a
quantization step (up to 0.08 on PETS09 and 0.15 on TUD-Stadtmitte, against peaks of about 1). What that does to the
people is measured, not assumed (docs/deploy.md, "Engines and operators").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vc.errors import InputError

#: The engines by name; the first is the default.
ENGINES = ("onnxruntime", "openvino")
DEFAULT_ENGINE = ENGINES[0]

#: A region's graph, ready: the crop in, the heat maps out.
GraphSession = Callable[[np.ndarray], np.ndarray]


def checked_engine(engine: str) -> str:
    """``engine`` if it is one of :data:`ENGINES`; an InputError naming the field otherwise."""
    if engine not in ENGINES:
        raise InputError(None, "engine", f"{engine!r} is not one of {', '.join(ENGINES)}")
    return engine


def onnxruntime_inference(model: bytes, threads: int):
    """An onnxruntime CPU session of ``model`` as the runtime runs every graph: ``threads`` intra-op threads that do
    not spin-wait after a run (regions run one after another: a session spinning after its run would take the cores
    from the next region's session)."""
    import onnxruntime as ort

    options = ort.SessionOptions()
    options.intra_op_num_threads = threads
    options.inter_op_num_threads = 1
    options.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
    options.add_session_config_entry("session.intra_op.allow_spinning", "0")
    return ort.InferenceSession(model, options, providers=["CPUExecutionProvider"])


def onnxruntime_session(model: bytes, threads: int) -> GraphSession:
    session = onnxruntime_inference(model, threads)
    input_name = session.get_inputs()[0].name
    return lambda crop: session.run(None, {input_name: crop})[0]


def openvino_session(model: bytes, threads: int) -> GraphSession:
    try:
        import openvino as ov
    except ImportError:
        raise InputError(None, "engine", "openvino is not installed (pip install openvino)") from None
    core = ov.Core()
    # f32 inference: on a CPU with bf16 instructions the plugin would otherwise run the float layers in bf16, which
    # is another network than the one the bundle was measured as
    compiled = core.compile_model(core.read_model(model), "CPU", {
        "INFERENCE_NUM_THREADS": threads, "INFERENCE_PRECISION_HINT": "f32", "PERFORMANCE_HINT": "LATENCY"})
    request = compiled.create_infer_request()  # one per region runner: a runner runs one frame at a time

    def run(crop: np.ndarray) -> np.ndarray:
        request.infer({0: crop})
        return request.get_output_tensor(0).data.copy()  # the tensor's memory is reused by the next frame
    return run


def graph_session(engine: str, model: bytes, threads: int) -> GraphSession:
    """``model`` (ONNX bytes) ready to run on ``engine`` with ``threads`` intra-op threads."""
    if checked_engine(engine) == "openvino":
        return openvino_session(model, threads)
    return onnxruntime_session(model, threads)
