"""Detectors trained on real photos, run on the same frames as a bundle so that vc-eval has something to compare
with. Each maps an (H, W, 3) uint8 RGB frame to :class:`Detections` in frame pixels.

- :class:`HogPeopleDetector`: OpenCV's HOG + linear SVM people detector (Dalal & Triggs, CVPR 2005, trained on
  the INRIA person photos). Its 64x128 window holds a person about 96 px tall with a 16 px margin on every side,
  so people smaller than that are missed unless the frame is upscaled, and its raw window boxes are too large to
  reach IoU 0.5 with a tight box: the box returned is the window shrunk by that margin.
- :class:`YoloPoseOnnx`: any ONNX model with YOLO-pose style output (Ultralytics' export: (1, 5 + 3K, N) or
  (1, N, 5 + 3K) rows of cx, cy, w, h, person confidence, K keypoints), fed a letterboxed square input. Its
  keypoints (x, y, confidence) come back with the boxes: what ``vc-eval`` compares the bundle's pose with.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import cv2
import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.engines import onnxruntime_inference
from vc.errors import InputError

#: The person inside HOG's 64x128 detection window (Dalal & Triggs 2005, section 3): 16 px margin on all sides.
HOG_WINDOW = (64, 128)
HOG_MARGIN = 16


class Detections(NamedTuple):
    """People found in one frame, in frame pixels."""

    boxes: np.ndarray  # (N, 4) x0, y0, x1, y1
    scores: np.ndarray  # (N,)
    keypoints: np.ndarray | None = None  # (N, K, 3) x, y, confidence; None from a detector without pose


class HogPeopleDetector:
    """OpenCV's default people detector over an image pyramid, on the frame upscaled ``upscale`` times."""

    def __init__(self, upscale: float = 2.0, hit_threshold: float = -0.5, scale_step: float = 1.05) -> None:
        self.upscale, self.hit_threshold, self.scale_step = upscale, hit_threshold, scale_step
        self.hog = cv2.HOGDescriptor()
        self.hog.setSVMDetector(cv2.HOGDescriptor_getDefaultPeopleDetector())

    def __call__(self, frame: np.ndarray) -> Detections:
        image = cv2.resize(frame, None, fx=self.upscale, fy=self.upscale, interpolation=cv2.INTER_LINEAR) \
            if self.upscale != 1.0 else frame
        rectangles, weights = self.hog.detectMultiScale(image, hitThreshold=self.hit_threshold, winStride=(8, 8),
                                                        padding=(16, 16), scale=self.scale_step)
        if len(rectangles) == 0:
            return Detections(np.zeros((0, 4)), np.zeros(0))
        x, y, width, height = np.asarray(rectangles, np.float64).T
        margin_x, margin_y = width * HOG_MARGIN / HOG_WINDOW[0], height * HOG_MARGIN / HOG_WINDOW[1]
        boxes = np.column_stack([x + margin_x, y + margin_y, x + width - margin_x, y + height - margin_y])
        return Detections(boxes / self.upscale, np.asarray(weights, np.float64).ravel())


def non_max_suppression(boxes: np.ndarray, scores: np.ndarray, iou_threshold: float) -> np.ndarray:
    """Indices of the boxes kept by greedy NMS, highest score first."""
    order = np.argsort(-scores, kind="stable")
    keep: list[int] = []
    while len(order):
        best, order = order[0], order[1:]
        keep.append(int(best))
        order = order[box_iou(boxes[best], boxes[order])[0] < iou_threshold]
    return np.array(keep, int)


#: Attributes per YOLO-pose row with COCO's 17 keypoints: box (4), person confidence, 17 x (x, y, visibility).
YOLO_POSE_ROW = 5 + 3 * 17


def _attributes_first(shape: tuple[int, int]) -> bool:
    """Whether an (A, N) output holds one detection per column (Ultralytics) rather than per row."""
    if (shape[0] == YOLO_POSE_ROW) != (shape[1] == YOLO_POSE_ROW):
        return shape[0] == YOLO_POSE_ROW
    return shape[0] < shape[1]


class YoloPoseOnnx:
    """A YOLO-pose ONNX model: boxes, person confidence and keypoints."""

    def __init__(self, path: Path, input_size: int | None = None, threads: int | None = None,
                 min_score: float = 0.001, iou_threshold: float = 0.7, max_detections: int = 300) -> None:
        try:
            # as the runtime's sessions, without spin-waiting after a run: timed beside a bundle in one process
            # (vc-eval), a spinning reference took the cores the bundle's next frame needed (a TUD-Stadtmitte frame,
            # 14.2 ms alone, 20.9 ms beside it, 17.2 ms beside it not spinning); it runs about 4 % slower itself
            # without spinning (110 -> 115 ms at 1280, 2-core AMD EPYC)
            self.session = onnxruntime_inference(Path(path).read_bytes(), threads or 0)
        except Exception as error:  # onnxruntime raises its own exception types for unreadable models
            raise InputError(path, "", f"cannot load as an ONNX model ({str(error).splitlines()[0]})") from None
        model_input = self.session.get_inputs()[0]
        fixed = model_input.shape[-1] if isinstance(model_input.shape[-1], int) else None
        self.size = input_size or fixed
        if self.size is None:
            raise InputError(path, "input", "the model's input size is dynamic: give it (e.g. 640)")
        self.input_name = model_input.name
        self.min_score, self.iou_threshold, self.max_detections = min_score, iou_threshold, max_detections

    def _letterbox(self, frame: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        height, width = frame.shape[:2]
        scale = min(self.size / width, self.size / height)
        new_width, new_height = round(width * scale), round(height * scale)
        pad = np.array([(self.size - new_width) // 2, (self.size - new_height) // 2])
        canvas = np.full((self.size, self.size, 3), 114, np.uint8)
        canvas[pad[1]:pad[1] + new_height, pad[0]:pad[0] + new_width] = cv2.resize(
            frame, (new_width, new_height), interpolation=cv2.INTER_LINEAR)
        return canvas.transpose(2, 0, 1)[None].astype(np.float32) / 255.0, scale, pad

    def __call__(self, frame: np.ndarray) -> Detections:
        tensor, scale, pad = self._letterbox(frame)
        output = np.asarray(self.session.run(None, {self.input_name: tensor})[0])[0]
        rows = output.T if _attributes_first(output.shape) else output  # (N, 5 + 3K)
        rows = rows[rows[:, 4] >= self.min_score]
        centre, size = rows[:, :2], rows[:, 2:4]
        boxes = (np.concatenate([centre - size / 2, centre + size / 2], axis=1) - np.tile(pad, 2)) / scale
        keep = non_max_suppression(boxes, rows[:, 4], self.iou_threshold)[:self.max_detections]
        # K from the row length, not -1: a frame without one row above min_score has no length to infer it from
        keypoints = rows[keep, 5:].reshape(len(keep), (rows.shape[1] - 5) // 3, 3).astype(np.float64)
        keypoints[:, :, :2] = (keypoints[:, :, :2] - pad) / scale
        return Detections(boxes[keep], rows[keep, 4].astype(np.float64), keypoints)
