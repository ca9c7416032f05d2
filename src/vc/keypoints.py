"""The 17 COCO keypoints: names, order and skeleton, shared by the renderer, the model and the runtime.

Plain constants (no numpy, no torch) so that the torch-free runtime can import them.
Order and names follow the COCO keypoint annotation format; the skeleton's indices are 1-based there
(``COCO_SKELETON_1BASED``, what ``annotations.json`` carries) and 0-based here for drawing.
"""

from __future__ import annotations

COCO_KEYPOINTS: tuple[str, ...] = (
    "nose",
    "left_eye",
    "right_eye",
    "left_ear",
    "right_ear",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
)

COCO_SKELETON_1BASED: tuple[tuple[int, int], ...] = (
    (16, 14), (14, 12), (17, 15), (15, 13), (12, 13), (6, 12), (7, 13), (6, 7), (6, 8), (7, 9),
    (8, 10), (9, 11), (2, 3), (1, 2), (1, 3), (2, 4), (3, 5), (4, 6), (5, 7),
)  # fmt: skip

COCO_SKELETON: tuple[tuple[int, int], ...] = tuple((a - 1, b - 1) for a, b in COCO_SKELETON_1BASED)

#: Index of each keypoint's mirror image (left <-> right), for horizontal-flip augmentation.
COCO_FLIP: tuple[int, ...] = tuple(
    COCO_KEYPOINTS.index(name.replace("left_", "@").replace("right_", "left_").replace("@", "right_"))
    for name in COCO_KEYPOINTS
)
