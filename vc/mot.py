"""Ground-truth boxes in the MOT Challenge text format: ``frame,id,left,top,width,height,...`` per line, frames
1-based (PETS 2009 S2.L1's published annotation uses it). Boxes come out as [x0, y0, x1, y1] in frame pixels."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vc.errors import InputError


def read_mot_boxes(path: Path) -> dict[int, np.ndarray]:
    """Frame number -> (N, 4) boxes; a frame without a line has no people (if within the annotated range)."""
    if not Path(path).is_file():
        raise InputError(path, "", "ground-truth file not found")
    boxes: dict[int, list[list[float]]] = {}
    for number, line in enumerate(Path(path).read_text().splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = line.replace(" ", "").split(",")
        try:
            frame, left, top, width, height = int(float(fields[0])), *map(float, fields[2:6])
        except (ValueError, IndexError):
            raise InputError(path, f"line {number}", "expected frame,id,left,top,width,height,...") from None
        if frame < 1 or width <= 0 or height <= 0:
            raise InputError(path, f"line {number}", "frame must be >= 1 and the box's width and height positive")
        boxes.setdefault(frame, []).append([left, top, left + width, top + height])
    if not boxes:
        raise InputError(path, "", "holds no boxes")
    return {frame: np.array(rows) for frame, rows in boxes.items()}
