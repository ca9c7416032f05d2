"""Acceptance: the Tsai model against real PETS 2009 ground truth (frames 1-400).

Each box's bottom centre is put on the ground; the height whose projection reaches the box top is solved for.
Real people are 1.70-1.80 m at the median, and the spread is that of people (and of hand-drawn boxes).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def solve_heights(camera, boxes: np.ndarray) -> np.ndarray:
    left, top, width, height = boxes.T
    feet = camera.ground_from_pixels(np.c_[left + width / 2, top + height])
    assert feet.ok.all(), "every ground-truth foot point must see the ground"
    heights = []
    for foot, box_top in zip(feet.points, top, strict=True):
        def top_gap(h, foot=foot, box_top=box_top):
            return camera.project(foot + [0.0, 0.0, h]).uv[1] - box_top
        heights.append(brentq(top_gap, 0.05, 5.0, xtol=1e-6))
    return np.array(heights)


def test_person_heights_from_ground_truth_boxes(pets_data, pets_camera):
    rows = np.loadtxt(pets_data / "gt_dev_frames_0001-0400.txt", delimiter=",")
    heights = solve_heights(pets_camera, rows[:, 2:6])
    p10, median, p90 = np.percentile(heights, [10, 50, 90])
    assert 1.70 <= median <= 1.80, median
    assert 1.55 <= p10 and p90 <= 1.95, (p10, p90)
