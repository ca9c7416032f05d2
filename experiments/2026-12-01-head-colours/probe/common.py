"""What the probes share: the halves, the pose reference's facing, and the low-capacity readers' inputs."""

from __future__ import annotations

import numpy as np

from vc.model.facing import camera_look, moved

#: camera -> (frames, ground truth, the halves (first, last, step)).
DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"
#: The probes' low-capacity readers: which part of the 64 x 32 crop (rows, columns), in colour or grey.
KINDS = {"grey_head": ((2, 18), (10, 22), False), "colour_head": ((2, 18), (10, 22), True),
         "grey_head2": ((0, 22), (8, 24), False), "colour_head2": ((0, 22), (8, 24), True),
         "grey_full": ((0, 64), (0, 32), False), "colour_full": ((0, 64), (0, 32), True)}


def reference_facing(keypoints: np.ndarray) -> int:
    """+1 seen from the front, -1 from behind, 0 unclear: the reference's shoulders and hips, as 0027 read them."""
    points = np.asarray(keypoints).reshape(17, 3)
    if points[[5, 6, 11, 12], 2].min() < 0.5:
        return 0
    share = sum(points[left, 0] - points[right, 0] for left, right in ((5, 6), (11, 12))) / max(np.ptp(points[:, 1]),
                                                                                              1.0)
    return 1 if share > 0.06 else (-1 if share < -0.06 else 0)


def iou(a: np.ndarray, b: np.ndarray) -> float:
    width, height = min(a[2], b[2]) - max(a[0], b[0]), min(a[3], b[3]) - max(a[1], b[1])
    if width <= 0 or height <= 0:
        return 0.0
    inter = width * height
    return float(inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter))


def cells(crops: np.ndarray, kind: str) -> np.ndarray:
    """A reader's input (N, D): its window in 2 x 2 cells, each crop's values less their mean over their spread + 4."""
    (r0, r1), (c0, c1), colour = KINDS[kind]
    x = crops[:, r0:r1, c0:c1].astype(np.float32)
    if not colour:
        x = x.mean(axis=3, keepdims=True)
    n, h, w, c = x.shape
    x = x.reshape(n, h // 2, 2, w // 2, 2, c).mean(axis=(2, 4)).reshape(n, -1)
    return (x - x.mean(1, keepdims=True)) / (x.std(1, keepdims=True) + 4.0)


def looks(crops: np.ndarray, rng: np.random.Generator, copies: int = 3) -> np.ndarray:
    """Each crop ``copies`` times in the camera's look, moved up to 3 rows and a column, mirrored half the time."""
    out = []
    for _ in range(copies):
        for crop in crops:
            look = moved(camera_look(crop, rng), int(rng.integers(-3, 4)), int(rng.integers(-1, 2)))
            out.append(look[:, ::-1] if rng.random() < 0.5 else look)
    return np.ascontiguousarray(np.array(out))
