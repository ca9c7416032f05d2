"""Where people stand: their feet on the ground in metres, and the scene's named zones they stand in (numpy only).

A bundle's manifest carries its camera (the scene's calibration) and, optionally, named ``zones``: polygons drawn
in frame pixels (``frame: image``) or on the ground in metres (``frame: ground``, the scene's ground coordinates).
A person is in a zone when their feet (the bottom centre of their box) are: tested in pixels for an image zone, on
the ground for a ground zone (so a zone keeps its shape in metres however the view foreshortens it). Feet above the
horizon have no ground point and are in no ground zone.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vc.calibration.camera import Camera, camera_from_dict
from vc.deploy.areas import ImageArea
from vc.errors import InputError

ZONE_FRAMES = ("image", "ground")


@dataclass(frozen=True)
class Zone:
    name: str
    frame: str  # "image" (frame pixels) or "ground" (metres)
    polygon: tuple[tuple[float, float], ...]

    def area(self) -> ImageArea:
        ring = [list(point) for point in self.polygon]
        return ImageArea({"type": "Polygon", "coordinates": [ring + [ring[0]]]})


def zones_from_manifest(manifest: dict, path: Path) -> list[Zone]:
    """The manifest's ``zones`` (none when absent), checked; a malformed one raises :class:`InputError`."""
    entries = manifest.get("zones", [])
    if not isinstance(entries, list):
        raise InputError(path, "manifest.json: zones", "expected a list of zones")
    zones, names = [], set()
    for index, entry in enumerate(entries):
        where = f"manifest.json: zones.{index}"
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str) or not entry["name"]:
            raise InputError(path, where, "a zone needs a name")
        if entry["name"] in names:
            raise InputError(path, f"{where}.name", f"{entry['name']!r} repeated: zone names are unique")
        if entry.get("frame") not in ZONE_FRAMES:
            raise InputError(path, f"{where}.frame", f"expected one of {', '.join(ZONE_FRAMES)}")
        try:
            polygon = np.asarray(entry.get("polygon"), np.float64)
        except (TypeError, ValueError):
            polygon = np.empty((0,))
        if polygon.ndim != 2 or polygon.shape[1] != 2 or len(polygon) < 3 or not np.isfinite(polygon).all():
            raise InputError(path, f"{where}.polygon", "expected at least three finite [x, y] points")
        names.add(entry["name"])
        zones.append(Zone(entry["name"], entry["frame"], tuple(map(tuple, polygon.tolist()))))
    return zones


class SceneZones:
    """Ground points and zones for feet in the frame of the camera ``camera`` (the bundle's)."""

    def __init__(self, camera: Camera | dict, zones: list[Zone]) -> None:
        self.camera = camera_from_dict(camera) if isinstance(camera, dict) else camera
        self.zones = zones
        self._areas = [zone.area() for zone in zones]

    def ground_points(self, feet: np.ndarray) -> np.ndarray:
        """(N, 2) ground x, y in metres of feet (N, 2) in frame pixels; NaN where the ray misses the ground."""
        feet = np.asarray(feet, np.float64).reshape(-1, 2)
        hit = self.camera.ground_from_pixels(feet)
        return np.where(hit.ok[:, None], hit.points[:, :2], np.nan)

    def zones_at(self, feet: np.ndarray, ground: np.ndarray) -> list[list[str]]:
        """The names of the zones each of the feet (N, 2) pixels, (N, 2) metres stands in, in the zones' order."""
        feet = np.asarray(feet, np.float64).reshape(-1, 2)
        ground = np.asarray(ground, np.float64).reshape(-1, 2)
        inside = np.zeros((len(self.zones), len(feet)), bool)
        on_ground = np.isfinite(ground).all(axis=1)
        for index, (zone, area) in enumerate(zip(self.zones, self._areas, strict=True)):
            if zone.frame == "image":
                inside[index] = area.contains(feet)
            elif on_ground.any():
                inside[index, on_ground] = area.contains(ground[on_ground])
        return [[zone.name for zone, flags in zip(self.zones, inside[:, k], strict=True) if flags]
                for k in range(len(feet))]
