"""Lower-precision variants of an exported region model, and what each costs in accuracy.

- ``fp16``: weights and arithmetic in half precision; the uint8 input and the float heat maps keep their types.
  Meant for GPUs and NPUs: a CPU without fp16 arithmetic runs it slower than fp32 (onnxruntime casts around
  every node).
- ``int8``: onnxruntime static quantization (QDQ: int8 weights per output channel, uint8 activations) of the
  network's operators (:data:`QUANTIZED_OPS`), calibrated on the region's training renders, the input excepted: the
  crop's pixels go into the first convolution as they are (:mod:`vc.model.quantized_input`). Heat-map heads are
  where int8 is known to break (peaks flatten into quantisation steps), so the export measures every precision on
  held-out renders and ``auto`` keeps int8 only where it holds.

The renders are region inputs; the deployed graph takes the region's crop of the frame and resizes it itself, so
renders are resized to the crop size (bilinear) before they go in: calibration and measurement see the graph as
the appliance runs it.
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import onnx
import onnxruntime as ort
from onnxruntime.quantization import CalibrationDataReader, QuantFormat, QuantType, quantize_static
from onnxruntime.quantization.shape_inference import quant_pre_process
from onnxruntime.transformers.float16 import convert_float_to_float16

from vc.deploy.decode import DecodeConfig
from vc.model.held_out import RegionEvaluation, evaluate_source
from vc.model.quantized_input import network_input_overrides, quantize_pixels_directly
from vc.render.dataset import Sample, read_sample

PRECISIONS = ("fp32", "fp16", "int8")
#: Every operator type of the network once batch norm is folded into the convolutions (docs/design.md, "Model"). The
#: ReLUs must be among them: quantized with the convolution before them, onnxruntime drops each ReLU into that
#: convolution's output range (zero point 0); left out, every convolution's output was dequantized, rectified in float
#: and quantized again. With them the networks run faster and their heat maps come closer to fp32
#: (docs/decisions/0004-network-architecture.md).
QUANTIZED_OPS = ("Conv", "Relu", "Add", "Concat")
#: The int8 scheme, here and for the crop models (:mod:`vc.model.crop_precision`): QDQ, uint8 activations, int8
#: weights per output channel.
INT8_SCHEME = {"quant_format": QuantFormat.QDQ, "activation_type": QuantType.QUInt8,
               "weight_type": QuantType.QInt8, "per_channel": True}
#: ``auto`` keeps int8 for a region when its held-out AP50 and PCKh@0.5 fall by at most this much from fp32.
AUTO_TOLERANCE = {"ap50": 0.01, "pckh": 0.02}


def crop_sized(image: np.ndarray, crop_size: tuple[int, int]) -> np.ndarray:
    """A region input (H, W, 3) uint8 as the crop of the frame it stands for (bilinear, like the graph's resize)."""
    if (image.shape[1], image.shape[0]) == tuple(crop_size):
        return image
    return cv2.resize(image, tuple(crop_size), interpolation=cv2.INTER_LINEAR)


class _Calibration(CalibrationDataReader):
    def __init__(self, samples: list[Sample], crop_size: tuple[int, int], input_name: str) -> None:
        self._batches: Iterator[dict] = ({input_name: crop_sized(read_sample(sample)[0], crop_size)[None]}
                                         for sample in samples)

    def get_next(self) -> dict | None:
        return next(self._batches, None)


def _input_name(model: bytes) -> str:
    return onnx.load_from_string(model).graph.input[0].name


def to_fp16(model: bytes) -> bytes:
    converted = convert_float_to_float16(onnx.load_from_string(model), keep_io_types=True)
    return converted.SerializeToString()


def to_int8(model: bytes, calibration: list[Sample], crop_size: tuple[int, int]) -> bytes:
    """Static int8 quantization of :data:`QUANTIZED_OPS`, activation ranges calibrated on ``calibration`` renders;
    the network's input quantized at the pixels' own levels and taken from the pixels directly
    (:mod:`vc.model.quantized_input`)."""
    with tempfile.TemporaryDirectory(prefix="vc-int8-") as folder:
        source, prepared, quantized = (Path(folder) / name for name in ("fp32.onnx", "pre.onnx", "int8.onnx"))
        source.write_bytes(model)
        quant_pre_process(str(source), str(prepared), skip_symbolic_shape=True)
        quantize_static(str(prepared), str(quantized), _Calibration(calibration, crop_size, _input_name(model)),
                        **INT8_SCHEME, op_types_to_quantize=list(QUANTIZED_OPS),
                        extra_options={"TensorQuantOverrides": network_input_overrides(onnx.load(str(prepared)))})
        return quantize_pixels_directly(onnx.load(str(quantized))).SerializeToString()


def convert(model: bytes, precision: str, calibration: list[Sample], crop_size: tuple[int, int]) -> bytes:
    """``model`` (fp32 bytes) at ``precision``."""
    if precision == "fp32":
        return model
    if precision == "fp16":
        return to_fp16(model)
    if precision == "int8":
        return to_int8(model, calibration, crop_size)
    raise ValueError(f"unknown precision {precision!r}; choose one of {', '.join(PRECISIONS)}")


def session(model: bytes, threads: int | None = None) -> ort.InferenceSession:
    options = ort.SessionOptions()
    if threads:
        options.intra_op_num_threads = threads
    options.log_severity_level = 3  # fp16 graphs warn about every cast they keep
    return ort.InferenceSession(model, options, providers=["CPUExecutionProvider"])


def evaluate_model(model: bytes, samples: list[Sample], crop_size: tuple[int, int], decode_config: DecodeConfig,
                   expected_height_px: np.ndarray, show_progress: bool = False,
                   description: str = "evaluate") -> RegionEvaluation:
    """Held-out accuracy of an exported model, fed crop-sized renders as the appliance would feed it."""
    runner = session(model)
    input_name = runner.get_inputs()[0].name

    def heatmaps_of(images: np.ndarray) -> np.ndarray:
        return np.concatenate([runner.run(None, {input_name: crop_sized(image, crop_size)[None]})[0]
                               for image in images])

    return evaluate_source(heatmaps_of, samples, decode_config, expected_height_px, show_progress, description)


@dataclass(frozen=True)
class PrecisionChoice:
    """The model kept for a region and the held-out accuracy (AP50, PCKh, mask IoU, ...) of every precision."""

    precision: str
    model: bytes
    accuracy: dict[str, dict]


def auto_precision(accuracy: dict[str, dict]) -> str:
    """int8 when it holds within :data:`AUTO_TOLERANCE` of fp32, else fp32."""
    reference, candidate = accuracy["fp32"], accuracy["int8"]
    holds = all(reference[metric] is None or (candidate[metric] is not None
                                               and reference[metric] - candidate[metric] <= tolerance)
                for metric, tolerance in AUTO_TOLERANCE.items())
    return "int8" if holds else "fp32"


def choose_precision(model: bytes, requested: str, calibration: list[Sample], held_out: list[Sample],
                     crop_size: tuple[int, int], decode_config: DecodeConfig, expected_height_px: np.ndarray,
                     show_progress: bool = False, region: str = "") -> PrecisionChoice:
    """Convert ``model`` (fp32) to every precision, measure each on ``held_out`` (skipped when it is empty) and
    keep ``requested`` (``auto``: see :func:`auto_precision`)."""
    if requested not in (*PRECISIONS, "auto"):
        raise ValueError(f"unknown precision {requested!r}; choose one of {', '.join(PRECISIONS)} or auto")
    if requested == "auto" and not held_out:
        raise ValueError("precision auto needs held-out samples to measure on")
    precisions = PRECISIONS if held_out else (requested,)
    models = {precision: convert(model, precision, calibration, crop_size) for precision in precisions}
    accuracy = {}
    for precision in precisions if held_out else ():
        evaluation = evaluate_model(models[precision], held_out, crop_size, decode_config, expected_height_px,
                                    show_progress, f"{region} {precision}").evaluation.to_dict()
        evaluation.pop("pckh_per_keypoint", None)
        accuracy[precision] = evaluation
    chosen = auto_precision(accuracy) if requested == "auto" else requested
    return PrecisionChoice(chosen, models[chosen], accuracy)
