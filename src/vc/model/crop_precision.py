"""The keypoint model at int8, where it holds (docs/decisions/0043-the-keypoint-model-at-int8-reads-twice.md).

Its graph takes the frame and the people's rectangles, cuts the crops (RoiAlign) and runs a network on each: its cost
is that network's, twice a person since it reads each crop and its mirror, and int8 halves it on a CPU. (The facing
model, quantized the same way, reads PETS09's people no faster and some of them worse, and stays fp32.)

1. Static QDQ quantization of the network's :data:`QUANTIZED_OPS` (int8 weights per output channel, uint8
   activations), as the region networks' (:mod:`vc.model.precision`); RoiAlign and the upsampling stay float.
2. Activation ranges calibrated on :data:`CALIBRATION_CROPS` of the compile's own training crops, chosen with its
   seed, each pasted into a frame and cut back out at its own size (:func:`side_by_side`): the graph as the
   runtime runs it.
3. The fp32 and int8 graphs are both measured on the held-out crops, and int8 is kept where it loses at most a
   tolerance (:func:`choose`); otherwise the graph ships fp32.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from onnxruntime.quantization import CalibrationDataReader, quantize_static
from onnxruntime.quantization.shape_inference import quant_pre_process

from vc.cores import usable_cores
from vc.deploy.crop_pose import MAPS_OUTPUT, keypoints_of_maps
from vc.deploy.engines import onnxruntime_inference
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT
from vc.model.crop_pose import PoseCrops, pckh
from vc.model.precision import AUTO_TOLERANCE, INT8_SCHEME

#: The networks' operators that run at int8 (step 1): as the region networks', the ReLUs among them so that each is
#: folded into the convolution before it.
QUANTIZED_OPS = ("Conv", "Relu", "Concat")
#: Training crops the activation ranges are calibrated on (step 2): as many as the region networks' renders.
CALIBRATION_CROPS = 64
#: Crops pasted into one frame, to read many crops at once, and to calibrate on (the ranges come out a little
#: different with other groupings).
CROPS_A_FRAME, CALIBRATION_CROPS_A_FRAME = 64, 8
#: int8 is kept where its PCKh@0.5 on the held-out crops is at most this much below fp32's (step 3), as a region's.
KEYPOINT_TOLERANCE = AUTO_TOLERANCE["pckh"]


def side_by_side(crops: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Crops (N, h, w, 3) uint8 pasted side by side into one frame input (1, h, N w, 3), and the rectangles (N, 4)
    that cut each back out at its own size."""
    count, height, width = crops.shape[:3]
    frame = np.ascontiguousarray(crops.transpose(1, 0, 2, 3).reshape(height, count * width, 3))[None]
    left = np.arange(count, dtype=np.float32) * width
    return frame, np.stack([left, np.zeros(count, np.float32), left + width, np.full(count, height, np.float32)],
                           axis=1)


def _graph_inputs(crops: np.ndarray, per_frame: int) -> Iterator[dict[str, np.ndarray]]:
    """A crop graph's inputs for ``crops``, ``per_frame`` pasted into each frame."""
    for start in range(0, len(crops), per_frame):
        yield dict(zip((FRAME_INPUT, ROIS_INPUT), side_by_side(crops[start:start + per_frame]), strict=True))


def read_crops(model: bytes, crops: np.ndarray, output: str) -> np.ndarray:
    """A crop graph's ``output`` for each of ``crops`` (N, h, w, 3) at the graph's crop size: (N, ...)."""
    session = onnxruntime_inference(model, usable_cores())
    return np.concatenate([session.run([output], inputs)[0] for inputs in _graph_inputs(crops, CROPS_A_FRAME)])


class _Calibration(CalibrationDataReader):
    def __init__(self, crops: np.ndarray) -> None:
        self._frames = _graph_inputs(crops, CALIBRATION_CROPS_A_FRAME)

    def get_next(self) -> dict | None:
        return next(self._frames, None)


def calibration_crops(crops: np.ndarray, seed: int) -> np.ndarray:
    """The :data:`CALIBRATION_CROPS` of ``crops`` (N, h, w, 3) the ranges are calibrated on, chosen with ``seed``."""
    chosen = np.random.default_rng(seed).choice(len(crops), min(CALIBRATION_CROPS, len(crops)), replace=False)
    return crops[np.sort(chosen)]


def to_int8(model: bytes, calibration: np.ndarray) -> bytes:
    """A crop graph (fp32 bytes) at int8, its ranges calibrated on ``calibration`` crops (steps 1-2)."""
    with tempfile.TemporaryDirectory(prefix="vc-int8-crops-") as folder:
        source, prepared, quantized = (Path(folder) / name for name in ("fp32.onnx", "pre.onnx", "int8.onnx"))
        source.write_bytes(model)
        quant_pre_process(str(source), str(prepared), skip_symbolic_shape=True)
        quantize_static(str(prepared), str(quantized), _Calibration(calibration), **INT8_SCHEME,
                        op_types_to_quantize=list(QUANTIZED_OPS))
        return quantized.read_bytes()


@dataclass(frozen=True)
class CropPrecision:
    """The graph kept, its precision and what each precision measured on the held-out crops."""

    precision: str
    model: bytes
    measured: dict[str, float | None]


def choose(model: bytes, calibration: np.ndarray, measure: Callable[[bytes], float | None],
           tolerance: float) -> CropPrecision:
    """``model`` (fp32) at int8 where ``measure`` (higher is better; None: nothing to measure on) of the int8 graph
    is within ``tolerance`` of the fp32 graph's, else fp32, as it is without ``calibration`` crops (step 3)."""
    if not len(calibration):  # nothing to calibrate on
        return CropPrecision("fp32", model, {"fp32": measure(model)})
    quantized = to_int8(model, calibration)
    measured = {"fp32": measure(model), "int8": measure(quantized)}
    holds = measured["fp32"] is None or (measured["int8"] is not None
                                         and measured["fp32"] - measured["int8"] <= tolerance)
    return CropPrecision("int8", quantized, measured) if holds else CropPrecision("fp32", model, measured)


def keypoints_at_int8(model: bytes, train: PoseCrops, held_out: PoseCrops, seed: int) -> CropPrecision:
    """The keypoint graph (fp32 bytes) at int8 where its held-out PCKh@0.5 holds (steps 1-3)."""

    def pckh_of(graph: bytes) -> float | None:
        if not len(held_out):
            return None
        height, width = held_out.crops.shape[1:3]
        rois = np.tile(np.array([[0, 0, width, height]], np.float32), (len(held_out), 1))
        measured = pckh(keypoints_of_maps(read_crops(graph, held_out.crops, MAPS_OUTPUT), rois), held_out)
        return None if measured is None else measured[0]

    return choose(model, calibration_crops(train.crops, seed), pckh_of, KEYPOINT_TOLERANCE)
