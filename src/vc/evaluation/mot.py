"""Ground-truth boxes in the MOT Challenge text format: ``frame,id,left,top,width,height,...`` per line, frames
1-based (PETS 2009 S2.L1's published annotation uses it). Boxes come out as [x0, y0, x1, y1] in frame pixels."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vc.errors import InputError


def _rows(path: Path, columns: int, expected: str):
    """(line number, numbers of the first ``columns`` fields) of every line that is not blank or a comment."""
    if not Path(path).is_file():
        raise InputError(path, "", "ground-truth file not found")
    for number, line in enumerate(Path(path).read_text().splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            values = [float(field) for field in line.replace(" ", "").split(",")[:columns]]
        except ValueError:
            values = []
        if len(values) < columns:
            raise InputError(path, f"line {number}", f"expected {expected}")
        yield number, values


def _box(path: Path, number: int, values: list[float]) -> list[float]:
    frame, _, left, top, width, height = values[:6]
    if frame < 1 or width <= 0 or height <= 0:
        raise InputError(path, f"line {number}", "frame must be >= 1 and the box's width and height positive")
    return [left, top, left + width, top + height]


def read_mot_boxes(path: Path) -> dict[int, np.ndarray]:
    """Frame number -> (N, 4) boxes; a frame without a line has no people (if within the annotated range)."""
    boxes: dict[int, list[list[float]]] = {}
    for number, values in _rows(path, 6, "frame,id,left,top,width,height,..."):
        boxes.setdefault(int(values[0]), []).append(_box(path, number, values))
    if not boxes:
        raise InputError(path, "", "holds no boxes")
    return {frame: np.array(rows) for frame, rows in boxes.items()}


def read_mot_world(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Boxes (N, 4) and their people's ground positions (N, 2, metres) from a ground truth that carries them in
    columns 8-9 (``frame,id,left,top,width,height,conf,x,y,z``, as MOTChallenge 2015's 3-D sets); boxes without
    a position (-1, -1) are left out."""
    boxes, ground = [], []
    for number, values in _rows(path, 9, "frame,id,left,top,width,height,conf,x,y,z with the ground position "
                                         "in x, y"):
        if values[7] == -1 and values[8] == -1 or not np.isfinite(values).all():
            continue
        boxes.append(_box(path, number, values))
        ground.append(values[7:9])
    return np.array(boxes).reshape(-1, 4), np.array(ground).reshape(-1, 2)


def read_mot_ids(path: Path) -> dict[int, np.ndarray]:
    """Frame number -> (N,) person ids, in the order of :func:`read_mot_boxes`' boxes."""
    ids: dict[int, list[int]] = {}
    for _, values in _rows(path, 6, "frame,id,left,top,width,height,..."):
        ids.setdefault(int(values[0]), []).append(int(values[1]))
    return {frame: np.array(values) for frame, values in ids.items()}
