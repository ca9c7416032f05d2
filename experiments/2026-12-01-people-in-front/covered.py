"""Recall of TUD-Stadtmitte's people by how much of their box nearer people's boxes cover (frozen; decision 0033).

    PYTHONPATH=../.. python covered.py BUNDLE

``vc-eval``'s evaluation of the bundle on both halves, tracked, as shipped. For each annotated person, the share of
their box that the boxes of people nearer the camera (a lower box bottom) cover, and whether the person was found,
by region (whose owned area holds the foot point).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import EvaluationRequest, evaluate_bundle

sys.path.insert(0, str(Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd"))
from measure import TUD  # noqa: E402  (the halves and the camera's files, as the arms measured them)

BINS = ((0.0, 0.01), (0.01, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.01))


def covered_share(boxes: np.ndarray, index: int) -> float:
    """The share of ``boxes[index]`` (x0, y0, x1, y1) under the boxes whose bottom is lower (nearer the camera)."""
    x0, y0, x1, y1 = boxes[index]
    grid = np.zeros((max(int(y1 - y0), 1), max(int(x1 - x0), 1)), bool)
    for other in boxes[boxes[:, 3] > y1]:
        left, right = int(max(other[0], x0) - x0), int(min(other[2], x1) - x0)
        top, bottom = int(max(other[1], y0) - y0), int(min(other[3], y1) - y0)
        if right > left and bottom > top:
            grid[top:bottom, left:right] = True
    return float(grid.mean())


def main() -> None:
    bundle = Path(sys.argv[1])
    for half, frames in TUD["halves"].items():
        with tempfile.TemporaryDirectory() as scratch:
            request = EvaluationRequest(bundle=bundle, video=TUD["video"], ground_truth=TUD["gt"], output=Path(scratch),
                                        frames=FrameRange.parse(frames), hog=False, threads=2,
                                        tracking=TrackingConfig(), fps=TUD["fps"])
            people = evaluate_bundle(request, show_progress=False).misses.people
        frames_people: dict[int, list] = {}
        for person in people:
            frames_people.setdefault(person.frame, []).append(person)
        rows = []
        for in_frame in frames_people.values():
            boxes = np.array([person.box for person in in_frame], float)
            rows += [(person.region, person.outcome == "found", covered_share(boxes, index))
                     for index, person in enumerate(in_frame)]
        for region in sorted({row[0] for row in rows if row[0]}):
            for low, high in BINS:
                chosen = [found for where, found, share in rows if where == region and low <= share < high]
                if chosen:
                    print(f"{half} {region}: box {low:.2f}-{min(high, 1.0):.2f} covered by nearer people's: "
                          f"{len(chosen)} people, recall {np.mean(chosen):.3f}")


if __name__ == "__main__":
    main()
