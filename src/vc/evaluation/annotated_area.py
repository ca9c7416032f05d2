"""Where a ground truth annotates people: the image area its people stand in (numpy and scipy only).

A ground truth often covers only part of a view. PETS09 S2.L1's boxes (A. Milan's annotation) all stand on one
patch of ground: no box in frames 1-400 has its feet above y = 154 or right of x = 753, and a path walked at the
top left of the frame (frames 126-176) and people half out of the frame are not annotated. A detector that finds
those people is scored as wrong, whoever's detector it is. Scoring only inside the annotated area tells that
apart from its real errors; it is reported beside the plain AP50, never instead of it.

The area is estimated from the ground truth alone: the convex hull of the foot points (the bottom centre of each
box) over every annotated frame. Annotators mark an area of ground; a convex area of the ground plane stays convex
through a pinhole camera, and the hull of the feet seen in it is the smallest area the annotation can cover. The
estimate is conservative: a detection just beyond the last annotated feet is still counted outside, and nothing
inside is ever left out.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from vc.deploy.boxes import foot_points
from vc.evaluation.metrics import Evaluation, ImageResult, evaluate

#: Fewer foot points than this span no area worth estimating: every detection is then inside.
MIN_FEET = 10


@dataclass(frozen=True)
class AnnotatedArea:
    """The convex image polygon (K, 2) that a ground truth's feet stand in; None where the ground truth spans no
    area (fewer than :data:`MIN_FEET` feet, or all on one line)."""

    polygon: np.ndarray | None
    feet: int  # foot points it was estimated from

    @classmethod
    def of(cls, truth: Mapping[int, np.ndarray]) -> AnnotatedArea:
        """From every annotated frame's boxes ({frame: (N, 4)}), whichever frames are scored."""
        feet = np.concatenate([foot_points(boxes) for boxes in truth.values()] or [np.zeros((0, 2))])
        if len(feet) < MIN_FEET:
            return cls(None, len(feet))
        try:
            hull = ConvexHull(feet)
        except QhullError:  # collinear or repeated feet: no area
            return cls(None, len(feet))
        return cls(feet[hull.vertices], len(feet))

    def contains(self, boxes: np.ndarray) -> np.ndarray:
        """Whether each box's feet (N,) stand in the area, its boundary included (all True without an area)."""
        feet = foot_points(boxes)
        if self.polygon is None:
            return np.ones(len(feet), bool)
        edges = np.roll(self.polygon, -1, axis=0) - self.polygon

        def side(points: np.ndarray) -> np.ndarray:  # (N, K): cross product of each edge with the point's offset
            offset = points[:, None, :] - self.polygon[None]
            return edges[None, :, 0] * offset[..., 1] - edges[None, :, 1] * offset[..., 0]

        # Inside a convex polygon = on the inner side of every edge, the side its centroid is on.
        inward = np.sign(side(self.polygon.mean(axis=0, keepdims=True)))
        return np.all(side(feet) * inward >= -1e-9, axis=1)

    def evaluate_inside(self, images: Sequence[ImageResult]) -> Evaluation:
        """``images`` scored as usual, except that a detection outside the area finding nobody is not held against
        the detector."""
        return evaluate([replace(image, detection_ignore=~self.contains(image.boxes)) for image in images])

    def to_dict(self) -> dict:
        return {"method": "convex hull of the ground truth's foot points, every annotated frame",
                "feet": self.feet,
                "polygon": None if self.polygon is None else [[round(float(x), 1), round(float(y), 1)]
                                                              for x, y in self.polygon]}
