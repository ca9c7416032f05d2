"""A clean background image from a video or a folder of frames: the per-pixel temporal median of evenly spaced
frames.

People move, the scene does not: at each pixel the median over enough frames is the empty scene, as long as
nobody stands still at that pixel for more than half of the sampled frames.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError


@dataclass(frozen=True)
class BackgroundResult:
    image: np.ndarray
    frames_in_video: int
    frame_indices: list[int]


def median_background(video: Path, max_frames: int = 150, progress: bool = True) -> BackgroundResult:
    """Median of up to ``max_frames`` frames spread evenly over a whole video or folder of frames (RGB uint8)."""
    video = Path(video)
    if max_frames < 3:
        raise InputError(None, "--frames", f"need at least 3 frames for a median, got {max_frames}")
    total = len(FrameSource(video))
    # Decoding sequentially and keeping every k-th frame is robust to containers whose seeking is inexact.
    source = FrameSource(video, FrameRange(1, None, max(1, total // max_frames)))
    frames, indices = [], []
    for frame in tqdm(source, total=min(len(source), max_frames), unit="frame", desc="reading",
                      disable=not progress):
        frames.append(frame.image)
        indices.append(frame.number - 1)
        if len(frames) == max_frames:
            break
    if len(frames) < 3:
        raise InputError(video, "", f"only {len(frames)} decodable frames; a median needs at least 3")
    shapes = {f.shape for f in frames}
    if len(shapes) != 1:
        raise InputError(video, "", f"frames change size within the video: {sorted(shapes)}")
    stack = np.stack(frames)
    median = np.median(stack, axis=0).round().astype(np.uint8)
    return BackgroundResult(median, total, indices)
