"""The sun over the background's day: where it stands each hour, and the background relit under it.

A camera in service sees the shadows of its scene swing round through the day, and people's shadows with them;
its background was photographed at one time. When a scene says where and when the background was taken
(``lighting: {location, time, north_deg}``) the sun's course follows, and the ``sun_course`` effect
(:mod:`vc.render.effects`) renders each sample under one position of it (issue 62: "sun positions through the day,
hard shadows cast by the layout and the people").

* **Positions** (:func:`sun_positions`): every :data:`STEP_HOURS` hours of the background's local date while the
  sun stands at least :data:`MIN_ELEVATION_DEG` high, plus the background's own. Its strength, colour and the sky
  stay as estimated from the background: a lower sun is not made weaker or redder (air mass), only moved.
* **The background relit** (:func:`shading_ratio`): differential rendering (Debevec, "Rendering Synthetic Objects
  into Real Scenes", SIGGRAPH 1998). The layout is rendered with a uniform grey ground under the moved sun and under
  the estimated one, through the same camera and with the same samples; the photograph times their ratio casts the
  layout's shadows where the moved sun puts them and lifts those it no longer casts. What the layout leaves out
  (an unmodelled tree's shadow) stays where the photograph has it.
* **People** are rendered under the moved sun by a renderer of their own per position
  (:class:`vc.render.synthesis.RegionSynthesizer` builds them as samples first need them).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from datetime import datetime, timedelta

import numpy as np

from vc.calibration.lighting import Illumination, solar_position
from vc.render.relight import shading_render
from vc.scenes.loader import Scene
from vc.scenes.schema import SolarLighting

#: Hours between the positions drawn: the sun's azimuth moves about 15 degrees an hour, so a shadow turns some
#: 30 degrees from one to the next; each position costs a renderer of its own per region (its build and kernels).
STEP_HOURS = 2.0
#: Positions lower than this are left out: their shadows run the length of the view and their light is the sky's.
MIN_ELEVATION_DEG = 15.0
#: Samples per pixel of the two shading renders a ratio divides (the same samples in both: their noise cancels
#: where the sun's visibility does not change).
RATIO_SPP = 32
#: Where the estimated light's shading is below this share of its median (the sky, beyond the horizon) the
#: background is left as photographed.
SHADING_FLOOR = 1e-3


@dataclass(frozen=True)
class SunPosition:
    """One position of the course: the local time and the sun's direction in the scene's frame."""

    time: str  # ISO 8601, the background's time zone
    azimuth_deg: float
    elevation_deg: float
    photographed: bool = False  # the background's own

    def to_dict(self) -> dict:
        return {"time": self.time, "azimuth_deg": round(self.azimuth_deg, 2),
                "elevation_deg": round(self.elevation_deg, 2), "photographed": self.photographed}

    @classmethod
    def from_dict(cls, data: dict) -> SunPosition:
        return cls(str(data["time"]), float(data["azimuth_deg"]), float(data["elevation_deg"]),
                   bool(data.get("photographed", False)))


def sun_positions(lighting: SolarLighting) -> list[SunPosition]:
    """The background's own position, then every :data:`STEP_HOURS` of its local date (whole hours on its clock)
    with the sun at least :data:`MIN_ELEVATION_DEG` high."""
    latitude, longitude = lighting.location
    taken = lighting.time
    azimuth, elevation = solar_position(latitude, longitude, taken, lighting.north_deg)
    positions = [SunPosition(taken.isoformat(), azimuth, elevation, photographed=True)]
    midnight = datetime.combine(taken.date(), datetime.min.time(), tzinfo=taken.tzinfo)
    for step in range(int(24 / STEP_HOURS)):
        moment = midnight + timedelta(hours=step * STEP_HOURS)
        azimuth, elevation = solar_position(latitude, longitude, moment, lighting.north_deg)
        if elevation >= MIN_ELEVATION_DEG:
            positions.append(SunPosition(moment.isoformat(), azimuth, elevation))
    return positions


def moved_sun(illumination: Illumination, position: SunPosition) -> Illumination:
    """``illumination`` with its sun moved to ``position`` (strength, colour and sky kept)."""
    return replace(illumination, sun_azimuth_deg=position.azimuth_deg, sun_elevation_deg=position.elevation_deg)


def shading_ratio(scene: Scene, estimated: Illumination, moved: Illumination, spp: int = RATIO_SPP,
                  estimated_shading: np.ndarray | None = None) -> np.ndarray:
    """(H, W, 3) float32: what the background's linear light is multiplied by to be lit by ``moved`` instead of
    ``estimated``, in the real camera's pixels: rendered and warped as the photograph was, so that the shadows' edges
    fall on its own (module docstring); 1 where the estimated shading is below :data:`SHADING_FLOOR` of its median.
    ``estimated_shading``: :func:`vc.render.relight.shading_render` of ``estimated`` at ``spp``, when the caller
    already has it (it is the same for every position)."""
    before = shading_render(scene, estimated, spp) if estimated_shading is None else estimated_shading
    after = shading_render(scene, moved, spp)
    floor = SHADING_FLOOR * max(float(np.median(before)), 1e-12)
    lit = before > floor
    ratio = np.ones_like(before)
    ratio[lit] = after[lit] / before[lit]
    return ratio.astype(np.float32)
