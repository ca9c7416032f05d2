"""A clean background image from a video or a folder of frames: the per-pixel temporal median of evenly spaced
frames.

People move, the scene does not: at each pixel the median over enough frames is the empty scene, as long as
nobody stands still at that pixel for more than half of the sampled frames. In a crowded street someone always
does, and the plain median keeps a ghost of them (TUD-Stadtmitte's: a man who waits by a shop window for most of
the clip, people lingering at a doorway). When the people's boxes are known (a ground truth such as the one
``vc-scene init --mot-world`` calibrates from), each frame contributes only the pixels outside every box, so the
median is taken over the frames in which that pixel shows the scene. Pixels covered in every sampled frame keep
the plain median and are counted, so that a ghost left behind is reported rather than silent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError

#: A person's box is grown by this share of its width on each side and of its height below before it is masked:
#: annotated boxes are tight, and arms, loose coats and the contact shadow at the feet spill out of them.
BOX_MARGIN = (0.15, 0.05)
#: Rows of the image whose median is taken at once (bounds the float copy of the frames to a band).
BAND_ROWS = 32


@dataclass(frozen=True)
class BackgroundResult:
    image: np.ndarray
    frames_in_video: int  # in the video, or in the frames chosen of it
    frame_indices: list[int]
    people_masked: bool = False
    #: share of the image covered by a person in every sampled frame (plain median there); 0 without boxes
    never_free_fraction: float = 0.0

    def to_dict(self) -> dict:
        height, width = self.image.shape[:2]
        method = "per-pixel temporal median" + (" of the frames where no person's box covers the pixel"
                                                if self.people_masked else "")
        return {"method": method, "size": [width, height], "frames_in_video": self.frames_in_video,
                "frames_used": len(self.frame_indices), "frame_indices": self.frame_indices,
                "people_masked": self.people_masked, "never_free_fraction": round(self.never_free_fraction, 5)}


def people_mask(shape: tuple[int, int], boxes: np.ndarray) -> np.ndarray:
    """Pixels (H, W bool) inside any of ``boxes`` ([x0, y0, x1, y1], outer edges) grown by :data:`BOX_MARGIN`."""
    height, width = shape
    mask = np.zeros(shape, bool)
    grow_x, grow_y = BOX_MARGIN
    for x0, y0, x1, y1 in np.asarray(boxes, float).reshape(-1, 4):
        margin_x = grow_x * (x1 - x0)
        left, right = int(np.clip(np.floor(x0 - margin_x), 0, width)), int(np.clip(np.ceil(x1 + margin_x), 0, width))
        top = int(np.clip(np.floor(y0), 0, height))
        bottom = int(np.clip(np.ceil(y1 + grow_y * (y1 - y0)), 0, height))
        mask[top:bottom, left:right] = True
    return mask


def _masked_median(stack: np.ndarray, covered: np.ndarray) -> tuple[np.ndarray, float]:
    """Per-pixel median of ``stack`` (T, H, W, C uint8) over the frames where ``covered`` (T, H, W) is False; the
    plain median where every frame is covered. Returns the image and the share of such pixels."""
    image = np.empty(stack.shape[1:], np.uint8)
    never_free = 0
    for top in range(0, stack.shape[1], BAND_ROWS):
        band = stack[:, top:top + BAND_ROWS].astype(np.float32)
        band_covered = covered[:, top:top + BAND_ROWS]
        always = band_covered.all(axis=0)
        never_free += int(always.sum())
        band_covered = band_covered & ~always  # those pixels fall back to every frame
        band[band_covered] = np.nan
        image[top:top + BAND_ROWS] = np.nanmedian(band, axis=0).round().astype(np.uint8)
    return image, never_free / float(covered[0].size)


def median_background(video: Path, max_frames: int = 150, progress: bool = True,
                      people: dict[int, np.ndarray] | None = None, frames: FrameRange | None = None
                      ) -> BackgroundResult:
    """Median of up to ``max_frames`` frames spread evenly over a whole video or folder of frames (RGB uint8), or
    over its ``frames``.

    ``people``: frame number (1-based, as the MOT Challenge format counts) -> that frame's boxes [x0, y0, x1, y1];
    each frame's pixels inside them are left out of the median (see the module docstring)."""
    video = Path(video)
    if max_frames < 3:
        raise InputError(None, "--frames", f"need at least 3 frames for a median, got {max_frames}")
    selection = frames or FrameRange()
    total = len(FrameSource(video, selection))
    # Decoding sequentially and keeping every k-th frame is robust to containers whose seeking is inexact.
    source = FrameSource(video, FrameRange(selection.first, selection.last,
                                           selection.step * max(1, total // max_frames)))
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
    if people is None:
        median = np.median(stack, axis=0).round().astype(np.uint8)
        return BackgroundResult(median, total, indices)
    covered = np.stack([people_mask(stack.shape[1:3], people.get(index + 1, np.zeros((0, 4)))) for index in indices])
    median, never_free = _masked_median(stack, covered)
    return BackgroundResult(median, total, indices, people_masked=True, never_free_fraction=never_free)
