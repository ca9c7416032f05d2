"""Image areas — a GeoJSON Polygon or MultiPolygon in frame pixels, as a bundle's manifest stores a region's owned
area — and which points lie in them (numpy only).

A point is in a polygon when a ray from it to the right crosses the polygon's rings an odd number of times. Over
all of a polygon's rings at once (outer ring and holes: valid GeoJSON keeps the holes inside the outer ring and
apart from each other) that is: inside the outer ring and outside every hole. So each polygon's edges are gathered
once into one array and a test is one vectorised pass per polygon, not one per ring with the ring's coordinates
converted again every frame (PETS09's r1 owns an area with 6 holes, one per obstacle, and the runtime tests feet
against its own area and its neighbours' up to eleven times a frame).
"""

from __future__ import annotations

import numpy as np


def _edges(ring: list) -> np.ndarray:
    """(M - 1, 4) edges x0, y0, x1, y1 of a closed ring of M points (the first repeated last, as in GeoJSON)."""
    points = np.asarray(ring, np.float64)
    return np.concatenate([points[:-1], points[1:]], axis=1)


class ImageArea:
    """A GeoJSON Polygon or MultiPolygon of image points, ready to test points against."""

    def __init__(self, geojson: dict) -> None:
        polygons = [geojson["coordinates"]] if geojson["type"] == "Polygon" else geojson["coordinates"]
        # Per polygon, all its rings' edges as (1, E) rows ready to broadcast against points: x0, y0, y1, the run
        # x1 - x0 and the rise y1 - y0, a horizontal edge's rise set to 1 (a ray never crosses it, so its crossing is
        # never read: no division by zero to silence, which costs more than the test).
        self._edge_rows = []
        for rings in polygons:
            x0, y0, x1, y1 = np.concatenate([_edges(ring) for ring in rings]).T[:, None, :]
            rise = y1 - y0
            self._edge_rows.append((x0, y0, y1, x1 - x0, np.where(rise == 0, 1.0, rise)))

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Whether each of the points (N, 2) lies in the area (even-odd rule, holes respected)."""
        points = np.asarray(points, np.float64).reshape(-1, 2)
        x, y = points[:, 0, None], points[:, 1, None]
        result = np.zeros(len(points), bool)
        for x0, y0, y1, run, rise in self._edge_rows:
            crosses = (y0 > y) != (y1 > y)
            x_cross = x0 + (y - y0) * run / rise
            result |= np.logical_xor.reduce(crosses & (x < x_cross), axis=1)  # an odd number of crossings
        return result


def in_area(points: np.ndarray, area: dict) -> np.ndarray:
    """Whether points (N, 2) lie in a GeoJSON Polygon or MultiPolygon (holes respected); to test one area many
    times, build its :class:`ImageArea` once."""
    return ImageArea(area).contains(points)
