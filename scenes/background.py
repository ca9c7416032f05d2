"""A clean background image from a video: the per-pixel temporal median of evenly spaced frames.

People move, the scene does not: at each pixel the median over enough frames is the empty scene, as long as
nobody stands still at that pixel for more than half of the sampled frames.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from vc.errors import InputError


@dataclass(frozen=True)
class BackgroundResult:
    image: np.ndarray
    frames_in_video: int
    frame_indices: list[int]


def _frame_count(capture: cv2.VideoCapture) -> int:
    return int(capture.get(cv2.CAP_PROP_FRAME_COUNT))


def median_background(video: Path, max_frames: int = 150, progress: bool = True) -> BackgroundResult:
    """Median of up to ``max_frames`` frames spread evenly over the whole video (RGB uint8)."""
    video = Path(video)
    if not video.is_file():
        raise InputError(video, "", "video file not found")
    if max_frames < 3:
        raise InputError(None, "--frames", f"need at least 3 frames for a median, got {max_frames}")
    capture = cv2.VideoCapture(str(video))
    try:
        if not capture.isOpened():
            raise InputError(video, "", "cannot open video (unknown container or codec)")
        total = _frame_count(capture)
        # Decoding sequentially and keeping every k-th frame is robust to containers whose seeking is inexact.
        stride = max(1, total // max_frames) if total > 0 else 1
        frames, indices = [], []
        with tqdm(total=total or None, unit="frame", desc="reading", disable=not progress) as bar:
            index = 0
            while len(frames) < max_frames:
                ok, frame = capture.read()
                if not ok:
                    break
                if index % stride == 0:
                    frames.append(cv2.cvtColor(frame, cv2.COLOR_BGR2RGB))
                    indices.append(index)
                index += 1
                bar.update(1)
    finally:
        capture.release()
    if len(frames) < 3:
        raise InputError(video, "", f"only {len(frames)} decodable frames; a median needs at least 3")
    shapes = {f.shape for f in frames}
    if len(shapes) != 1:
        raise InputError(video, "", f"frames change size within the video: {sorted(shapes)}")
    stack = np.stack(frames)
    median = np.median(stack, axis=0).round().astype(np.uint8)
    return BackgroundResult(median, total, indices)
