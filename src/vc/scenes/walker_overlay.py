"""The people a camera was solved from, drawn over its background (``vc-scene init`` without points writes it as
``walkers.png``): each sighting's head-to-foot line, green where the fit kept it and red where it was dropped as not
an adult standing upright, and, at each kept head, a yellow tick where the solved camera puts the head of a person
of the prior's stature standing on those feet. Where the ticks sit on the lines' tops, the camera explains the
people; the horizon is drawn too, and the solution with its uncertainty is written in the corner."""

from __future__ import annotations

import cv2
import numpy as np

from vc.calibration.from_people import PeopleCalibration, predicted_heads
from vc.calibration.walkers import Sighting
from vc.scenes.overlay import draw_horizon, draw_label

KEPT_COLOUR = (60, 230, 90)
DROPPED_COLOUR = (255, 60, 60)
MODEL_COLOUR = (255, 230, 0)
#: Half the width of the tick marking the model's head (px).
TICK_PX = 3


def solution_lines(calibration: PeopleCalibration) -> list[str]:
    """The solution and its uncertainty, one short line each (what ``vc-scene init`` prints too)."""
    spread = calibration.spread
    focal = (f"focal {calibration.focal_px:.0f} px (given)" if calibration.focal_given else
             f"focal {calibration.focal_px:.0f} px +-{spread.get('focal_px', 0.0):.0f}")
    return [f"{focal}, tilt {calibration.tilt_deg:.1f} deg +-{spread.get('tilt_deg', 0.0):.1f}, "
            f"roll {calibration.roll_deg:.1f} deg +-{spread.get('roll_deg', 0.0):.1f}",
            f"{calibration.height_m:.2f} m +-{spread.get('height_m', 0.0):.2f} above the ground, for people "
            f"{calibration.stature_m:.2f} m tall on average",
            f"{calibration.sightings} sightings of {calibration.tracks} people kept, "
            f"{int((~calibration.inliers).sum())} dropped"]


def draw_walkers(background: np.ndarray, sightings: list[Sighting], calibration: PeopleCalibration) -> np.ndarray:
    """(H, W, 3) uint8 RGB: ``background`` with the ``sightings`` (in the order the calibration was solved from)
    and the solved camera's reading of them."""
    image = background.copy()
    feet = np.array([sighting.foot for sighting in sightings], np.float64).reshape(-1, 2)
    heads = np.array([sighting.head for sighting in sightings], np.float64).reshape(-1, 2)
    for head, foot, kept in zip(heads, feet, calibration.inliers, strict=True):
        colour = KEPT_COLOUR if kept else DROPPED_COLOUR
        cv2.line(image, tuple(np.round(head).astype(int)), tuple(np.round(foot).astype(int)), colour, 1, cv2.LINE_AA)
    model, ok = predicted_heads(calibration.camera, feet, calibration.stature_m)
    for (u, v) in model[ok & calibration.inliers]:
        cv2.line(image, (int(round(u)) - TICK_PX, int(round(v))), (int(round(u)) + TICK_PX, int(round(v))),
                 MODEL_COLOUR, 1, cv2.LINE_AA)
    draw_horizon(image, calibration.camera)
    for row, text in enumerate(solution_lines(calibration)):
        draw_label(image, text, (4, 16 + 18 * row), (255, 255, 255))
    return image
