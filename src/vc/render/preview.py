"""A contact sheet of rendered samples with their labels drawn: the quick look before spending hours rendering.

Per person: the visible mask tinted in the person's colour, the box, the skeleton, and the keypoints — filled
dots where visible (v = 2), hollow where occluded (v = 1). Drawn at 2x so that small people stay readable.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import cv2
import numpy as np

from vc.keypoints import COCO_SKELETON
from vc.render.synthesis import RenderedSample
from vc.scenes.overlay import PALETTE

MASK_OPACITY = 0.4
ZOOM = 2
SHEET_COLUMNS = 3
LABEL_HEIGHT_PX = 22


def _point(xy: Sequence[float]) -> tuple[int, int]:
    """Project pixel coordinates -> OpenCV drawing coordinates at ZOOM (pixel centres at (i + 0.5) * ZOOM)."""
    return int(round((xy[0] + 0.5) * ZOOM)), int(round((xy[1] + 0.5) * ZOOM))


def draw_sample(sample: RenderedSample) -> np.ndarray:
    """The sample's image at ZOOM with masks, boxes, skeletons and keypoints drawn (RGB uint8)."""
    image = sample.image.astype(np.float32)
    for annotation in sample.annotations:
        colour = np.array(PALETTE[(annotation["instance_id"] - 1) % len(PALETTE)], np.float32)
        mask = sample.instances == annotation["instance_id"]
        image[mask] = (1 - MASK_OPACITY) * image[mask] + MASK_OPACITY * colour
    canvas = cv2.resize(image.astype(np.uint8), None, fx=ZOOM, fy=ZOOM, interpolation=cv2.INTER_NEAREST)
    for annotation in sample.annotations:
        colour = PALETTE[(annotation["instance_id"] - 1) % len(PALETTE)]
        x, y, w, h = annotation["bbox"]
        cv2.rectangle(canvas, (int(x * ZOOM + ZOOM / 2), int(y * ZOOM + ZOOM / 2)),
                      (int((x + w) * ZOOM + ZOOM / 2) - 1, int((y + h) * ZOOM + ZOOM / 2) - 1), colour, 1)
        keypoints = np.asarray(annotation["keypoints"], np.float64).reshape(-1, 3)
        for a, b in COCO_SKELETON:
            if keypoints[a, 2] > 0 and keypoints[b, 2] > 0:
                cv2.line(canvas, _point(keypoints[a, :2]), _point(keypoints[b, :2]), (255, 255, 255), 1,
                         cv2.LINE_AA)
        for u, v, visibility in keypoints:
            if visibility > 0:
                cv2.circle(canvas, _point((u, v)), 2, colour, -1 if visibility == 2 else 1, cv2.LINE_AA)
    return canvas


def contact_sheet(samples: Sequence[tuple[str, RenderedSample]], tile_width: int = 640) -> np.ndarray:
    """Tiles of :func:`draw_sample`, each titled (region and index), in rows of :data:`SHEET_COLUMNS`."""
    tiles = []
    for title, sample in samples:
        drawn = draw_sample(sample)
        scale = tile_width / drawn.shape[1]
        drawn = cv2.resize(drawn, (tile_width, max(1, round(drawn.shape[0] * scale))), interpolation=cv2.INTER_AREA)
        label = np.full((LABEL_HEIGHT_PX, tile_width, 3), 24, np.uint8)
        people = len(sample.annotations)
        cv2.putText(label, f"{title}  ({people} {'person' if people == 1 else 'people'})", (6, 16),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1, cv2.LINE_AA)
        tiles.append(np.concatenate([label, drawn]))
    tile_height = max(tile.shape[0] for tile in tiles)
    rows = math.ceil(len(tiles) / SHEET_COLUMNS)
    sheet = np.full((rows * tile_height, SHEET_COLUMNS * tile_width, 3), 12, np.uint8)
    for index, tile in enumerate(tiles):
        row, column = divmod(index, SHEET_COLUMNS)
        sheet[row * tile_height:row * tile_height + tile.shape[0],
              column * tile_width:(column + 1) * tile_width] = tile
    return sheet
