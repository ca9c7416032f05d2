"""The facing model and the keypoint model at int8, as the region networks ship (frozen, issue 57's time budget):
static QDQ quantization of their convolutions, ReLUs and concatenations, per-channel weights, activation ranges
calibrated on 64 of the compile's own render crops (as vc.model.precision calibrates the regions on 64 renders);
RoiAlign, the head reader and the heads' last layers stay float. Measured on the compile's held-out render crops
against fp32, and timed.

    PYTHONPATH=src python experiments/2026-12-01-int8-crop-models/quantize.py BUNDLE RENDERS SEED WORK \
        >> experiments/2026-12-01-int8-crop-models/results/quantize.jsonl

WORK/bundle is the bundle with both models at int8 (the region networks as shipped).
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import onnx
from onnxruntime.quantization import CalibrationDataReader, QuantFormat, QuantType, quantize_static
from onnxruntime.quantization.shape_inference import quant_pre_process

from vc.deploy.bundle import CROP_POSE, FACING, MANIFEST, sha256
from vc.deploy.crop_pose import MAPS_OUTPUT, keypoints_of_maps
from vc.deploy.engines import onnxruntime_inference
from vc.deploy.facing import FRAME_INPUT, OUTPUT_NAME, ROIS_INPUT
from vc.model.crop_pose import dataset_crops as pose_crops
from vc.model.crop_pose import pckh
from vc.model.export import write_bundle
from vc.model.facing import dataset_crops as facing_crops
from vc.model.facing import ranking

CALIBRATION_CROPS = 64
QUANTIZED_OPS = ["Conv", "Relu", "Concat"]  # Gemm (the heads' last layer) and the head reader stay float
SIDE_BY_SIDE = 64  # crops read a call, pasted side by side into one frame


def side_by_side(crops: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Crops (N, h, w, 3) pasted side by side into one frame input (1, h, N w, 3), and the rectangles that cut each
    back out at its own size."""
    count, height, width = crops.shape[:3]
    frame = np.ascontiguousarray(crops.transpose(1, 0, 2, 3).reshape(height, count * width, 3))[None]
    left = np.arange(count, dtype=np.float32) * width
    return frame, np.stack([left, np.zeros(count, np.float32), left + width, np.full(count, height, np.float32)], 1)


class Calibration(CalibrationDataReader):
    def __init__(self, crops: np.ndarray) -> None:
        self.batches = iter([dict(zip((FRAME_INPUT, ROIS_INPUT), side_by_side(crops[index:index + 8]), strict=True))
                             for index in range(0, len(crops), 8)])

    def get_next(self) -> dict | None:
        return next(self.batches, None)


def to_int8(model: bytes, calibration: np.ndarray) -> bytes:
    graph = onnx.load_from_string(model)
    kept = {}
    for entry in graph.opset_import:  # the merged crop graphs name the default domain twice
        kept.setdefault(entry.domain, entry.version)
    del graph.opset_import[:]
    graph.opset_import.extend([onnx.helper.make_opsetid(domain, version) for domain, version in kept.items()])
    with tempfile.TemporaryDirectory(prefix="vc-int8-crops-") as folder:
        source, prepared, quantized = (Path(folder) / name for name in ("fp32.onnx", "pre.onnx", "int8.onnx"))
        onnx.save(graph, str(source))
        quant_pre_process(str(source), str(prepared), skip_symbolic_shape=True)
        quantize_static(str(prepared), str(quantized), Calibration(calibration), quant_format=QuantFormat.QDQ,
                        activation_type=QuantType.QUInt8, weight_type=QuantType.QInt8, per_channel=True,
                        op_types_to_quantize=QUANTIZED_OPS)
        return quantized.read_bytes()


def read(model: bytes, crops: np.ndarray, output: str) -> tuple[np.ndarray, float]:
    """The model's ``output`` for each crop, and the milliseconds a crop took (one thread)."""
    session = onnxruntime_inference(model, 1)
    readings, seconds = [], 0.0
    for index in range(0, len(crops), SIDE_BY_SIDE):
        frame, rois = side_by_side(crops[index:index + SIDE_BY_SIDE])
        start = time.perf_counter()
        readings.append(session.run([output], {FRAME_INPUT: frame, ROIS_INPUT: rois})[0])
        seconds += time.perf_counter() - start
    return np.concatenate(readings), 1e3 * seconds / len(crops)


def main() -> None:
    bundle, renders, seed, work = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4])
    manifest = json.loads((bundle / MANIFEST).read_text())
    files = {str(path.relative_to(bundle)): path.read_bytes() for path in bundle.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    row: dict = {"bundle": str(bundle), "seed": seed}
    facing_train, facing_held = facing_crops(renders)
    rng = np.random.default_rng(seed)
    member = manifest[FACING]["model"]
    fp32 = files[member]
    int8 = to_int8(fp32, facing_train.facing.crops[rng.choice(len(facing_train.facing), CALIBRATION_CROPS, False)])
    held = facing_held.facing
    for name, model in (("fp32", fp32), ("int8", int8)):
        logits, ms = read(model, held.crops, OUTPUT_NAME)
        logits = logits.reshape(-1)
        row[f"facing {name}"] = {"accuracy": round(float(((logits > 0) == held.front).mean()), 4),
                                 "auc": round(float(ranking(logits, held.front)), 4), "ms_a_crop": round(ms, 3),
                                 "kB": len(model) // 1024, "people": len(held)}
    manifest = {**manifest, FACING: {**manifest[FACING], "model_sha256": sha256(int8)}}
    files[member] = int8
    if CROP_POSE in manifest:
        train, held_out = pose_crops(renders, seed, 80.0)
        member = manifest[CROP_POSE]["model"]
        fp32 = files[member]
        int8 = to_int8(fp32, train.crops[rng.choice(len(train), CALIBRATION_CROPS, False)])
        for name, model in (("fp32", fp32), ("int8", int8)):
            maps, ms = read(model, held_out.crops, MAPS_OUTPUT)
            width = held_out.crops.shape[2]
            rois = np.tile(np.array([[0, 0, width, held_out.crops.shape[1]]], np.float32), (len(maps), 1))
            row[f"keypoint model {name}"] = {"pckh": round(pckh(keypoints_of_maps(maps, rois), held_out)[0], 4),
                                             "ms_a_crop": round(ms, 3), "kB": len(model) // 1024,
                                             "people": len(held_out)}
        manifest = {**manifest, CROP_POSE: {**manifest[CROP_POSE], "model_sha256": sha256(int8)}}
        files[member] = int8
    if not (work / "bundle" / MANIFEST).is_file():
        write_bundle(manifest, files, work / "bundle", as_zip=False)
    print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
