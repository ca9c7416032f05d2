"""People walking alone through a camera's view, found without a network: their head and foot points, by track
(the input of :mod:`vc.calibration.from_people`).

Why no detector: a scene-specific network needs the scene, which needs the camera being solved; a generic one
trained on real images is what this project does not use. What a calibration needs is less than detection: a
number of upright people, each seen whole and alone, in many places. Against the video's median background
(:mod:`vc.scenes.background`) a walker alone is a blob of changed pixels about three times as tall as it is wide;
its top is the head, its bottom the feet (Lv, Zhao & Nevatia, PAMI 2006, calibrate from such blobs). What is not a
walker alone mostly fails the blob's shape (groups, cars, a cyclist's wheels, a person cut by the frame), and what
passes anyway (a child, a shadow joined to the feet) is left to the solver's outlier rejection.

1. **Changed pixels**: a pixel changed when some channel differs from the background by more than
   :data:`CHANGE_SIGMAS` of the frame's own difference noise (its median absolute difference, robust to the
   people), and at least :data:`MIN_CHANGE_CODES`, unless it is the background in a shadow (:func:`shadow_pixels`):
   the contact shadow would lower the feet.
2. **Blobs**: the mask opened (specks) and closed (a person split at the belt), then its connected components.
3. **Walkers alone**: a blob is kept when it is at least :data:`MIN_HEIGHT_SHARE` of the frame's height tall, between
   :data:`ASPECT` times as tall as wide, fills at least :data:`MIN_FILL` of its box, and keeps :data:`BORDER_PX` from
   the frame's edges (a person cut by the edge has no feet or no head). Its head and feet are where its body axis
   (:func:`body_axis`) crosses its top and bottom rows.
4. **Tracks**: a blob in one sampled frame continues the track of the previous sampled frame's blob it overlaps most
   (IoU at least :data:`TRACK_IOU`); tracks seen fewer than :data:`MIN_SIGHTINGS` times are dropped, and so are
   sightings of a walker partly hidden behind a post or a sign (:func:`whole`).

Measured against PETS09's calibration (experiments/2026-11-30-walkers-shadow-and-hidden): without the shadow test
the walkers stood 1.80 m on the median, with it 1.69 m.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from vc.deploy.frames import FrameRange, FrameSource
from vc.errors import InputError

#: A pixel changed beyond this many robust deviations of the frame's difference from the background ...
CHANGE_SIGMAS = 5.0
#: ... and by at least this many codes.
MIN_CHANGE_CODES = 20
#: A shadow darkens the background by a ratio within these bounds, and changes its saturation and hue (both 0-1)
#: by at most these (Cucchiara et al. 2003): the contact shadow would otherwise lower the feet.
SHADOW_DARKENING = (0.4, 0.93)
SHADOW_SATURATION = 0.15
SHADOW_HUE = 0.5
#: A walker is at least this share of the frame's height tall ...
MIN_HEIGHT_SHARE = 0.05
#: ... between these many times as tall as wide ...
ASPECT = (1.8, 5.0)
#: ... fills this share of its box ...
MIN_FILL = 0.4
#: ... and keeps this far from the frame's edges (pixels).
BORDER_PX = 3
#: A blob continues the track it overlaps by this IoU or more ...
TRACK_IOU = 0.3
#: ... and a track seen fewer times than this is dropped.
MIN_SIGHTINGS = 3
#: A sighting shorter than this share of the tallest of its track's neighbours, this many each side, is partly
#: hidden and dropped.
PARTLY_HIDDEN_SHARE = 0.9
NEIGHBOURS = 3


@dataclass(frozen=True)
class Sighting:
    """One walker alone in one frame."""

    frame: int
    track: int
    head: tuple[float, float]
    foot: tuple[float, float]
    box: tuple[int, int, int, int]  # x0, y0, x1, y1 (exclusive)


def shadow_pixels(frame: np.ndarray, background: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels of ``frame`` where the background only lies in a shadow: darker by a ratio within
    :data:`SHADOW_DARKENING` and of the same saturation and hue (Cucchiara et al., PAMI 2003; their thresholds)."""
    seen = cv2.cvtColor(frame, cv2.COLOR_RGB2HSV_FULL).astype(np.float32) / 255.0
    lit = cv2.cvtColor(background, cv2.COLOR_RGB2HSV_FULL).astype(np.float32) / 255.0
    ratio = seen[..., 2] / np.maximum(lit[..., 2], 1.0 / 255.0)
    hue = np.abs(seen[..., 0] - lit[..., 0])
    hue = np.minimum(hue, 1.0 - hue)
    return ((ratio >= SHADOW_DARKENING[0]) & (ratio <= SHADOW_DARKENING[1])
            & (np.abs(seen[..., 1] - lit[..., 1]) <= SHADOW_SATURATION) & (hue <= SHADOW_HUE))


def changed_pixels(frame: np.ndarray, background: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels of ``frame`` that differ from ``background`` (both (H, W, 3) uint8) other than by a
    shadow, step 1."""
    difference = np.abs(frame.astype(np.int16) - background.astype(np.int16)).max(axis=2)
    sigma = 1.4826 * float(np.median(difference))
    return (difference > max(MIN_CHANGE_CODES, CHANGE_SIGMAS * sigma)) & ~shadow_pixels(frame, background)


def walkers_in(mask: np.ndarray) -> list[tuple[tuple[int, int, int, int], tuple[float, float], tuple[float, float]]]:
    """The walkers alone among a changed-pixel ``mask``'s blobs (steps 2-3): (box, head, foot) each."""
    height, width = mask.shape
    cleaned = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    cleaned = cv2.morphologyEx(cleaned, cv2.MORPH_CLOSE, np.ones((9, 5), np.uint8))
    count, labels, stats, _ = cv2.connectedComponentsWithStats(cleaned, connectivity=8)
    found = []
    for label in range(1, count):
        x, y, w, h, area = (int(value) for value in stats[label])
        if h < MIN_HEIGHT_SHARE * height or not ASPECT[0] <= h / max(w, 1) <= ASPECT[1] or area < MIN_FILL * w * h:
            continue
        if x < BORDER_PX or y < BORDER_PX or x + w > width - BORDER_PX or y + h > height - BORDER_PX:
            continue
        top_x, bottom_x = body_axis(labels[y:y + h, x:x + w] == label)
        found.append(((x, y, x + w, y + h), (top_x + x, float(y)), (bottom_x + x, float(y + h - 1))))
    return found


def body_axis(blob: np.ndarray) -> tuple[float, float]:
    """Where a walker's body axis crosses the top and the bottom rows of their ``blob`` (a (h, w) bool mask):
    the line through the middles of its rows, fitted by least squares weighted by each row's pixels.

    Not the middles of the end rows themselves: the highest pixels of a leaning body are at the side its top leans
    from, and its lowest at the other, so end rows read the lean short. On walkers drawn through a known camera the
    end rows put its vertical vanishing point 30 % too far (focal length +15 %, tilt -2 degrees; decision 0029)."""
    counts = blob.sum(axis=1).astype(np.float64)
    rows = np.flatnonzero(counts)
    middles = (blob[rows] * np.arange(blob.shape[1])).sum(axis=1) / counts[rows]
    if len(rows) < 2:
        return float(middles[0]), float(middles[0])
    slope, offset = np.polyfit(rows.astype(np.float64), middles, 1, w=np.sqrt(counts[rows]))
    return float(offset), float(offset + slope * (blob.shape[0] - 1))


def _iou(a: tuple[int, int, int, int], b: tuple[int, int, int, int]) -> float:
    inter_w = min(a[2], b[2]) - max(a[0], b[0])
    inter_h = min(a[3], b[3]) - max(a[1], b[1])
    if inter_w <= 0 or inter_h <= 0:
        return 0.0
    inter = inter_w * inter_h
    return inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter)


def track_walkers(frames: Iterable[tuple[int, np.ndarray]], background: np.ndarray) -> list[Sighting]:
    """Every walker alone in ``frames`` ((number, (H, W, 3) uint8 RGB) pairs, in order), by track (step 4)."""
    sightings: list[Sighting] = []
    previous: list[Sighting] = []
    next_track = 0
    for number, frame in frames:
        current = []
        for box, head, foot in walkers_in(changed_pixels(frame, background)):
            overlaps = [(_iou(box, seen.box), seen.track) for seen in previous]
            best = max(overlaps, default=(0.0, -1))
            if best[0] >= TRACK_IOU and all(seen.track != best[1] for seen in current):
                track = best[1]
            else:
                track, next_track = next_track, next_track + 1
            current.append(Sighting(number, track, head, foot, box))
        sightings.extend(current)
        previous = current
    by_track: dict[int, list[Sighting]] = {}
    for sighting in sightings:
        by_track.setdefault(sighting.track, []).append(sighting)
    return [sighting for track in by_track.values() if len(track) >= MIN_SIGHTINGS for sighting in whole(track)]


def walkers_in_video(video: Path, background: np.ndarray, frames: FrameRange | None = None,
                     progress: bool = True) -> list[Sighting]:
    """Every walker alone in the ``frames`` (default: all) of a video or folder of frames (:func:`track_walkers`),
    read once."""
    source = FrameSource(video, frames or FrameRange())
    if source.kind == "image":
        raise InputError(video, "", "one image shows no one walking: the camera is solved from people walking "
                                    "through a video (or a folder of its frames), else give --points or "
                                    "--calibration")

    def images() -> Iterable[tuple[int, np.ndarray]]:
        for frame in tqdm(source, total=len(source), unit="frame", desc="walkers", disable=not progress):
            if frame.image.shape != background.shape:
                raise InputError(video, "", f"frame {frame.number} is {frame.image.shape[1]}x{frame.image.shape[0]}"
                                            f", the background {background.shape[1]}x{background.shape[0]}")
            yield frame.number, frame.image

    return track_walkers(images(), background)


def whole(track: list[Sighting]) -> list[Sighting]:
    """The sightings of one ``track`` (in frame order) not shorter than :data:`PARTLY_HIDDEN_SHARE` of the tallest of
    their :data:`NEIGHBOURS` each side: a walker stepping behind a post or a sign loses part of their blob at once,
    while one walking away shrinks slowly."""
    heights = np.array([sighting.foot[1] - sighting.head[1] for sighting in track])
    kept = []
    for index, sighting in enumerate(track):
        around = heights[max(0, index - NEIGHBOURS):index + NEIGHBOURS + 1]
        if heights[index] >= PARTLY_HIDDEN_SHARE * around.max():
            kept.append(sighting)
    return kept
