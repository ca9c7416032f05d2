"""The scene as a browser page edits it: its layout and zones in pixels of the background, drawn through the
camera, and saved back into ``scene.yaml`` in the frame the scene uses (``vc-scene edit``,
:mod:`vc.scenes.editor_server`).

An installer has the background and a browser, not a site plan. The page shows the background with the ground grid
in metres, the horizon and the region plan drawn through the scene's camera, and person figures of the prior's
statures where the mouse points; the user draws and moves the walkable polygons, obstacles (a cylinder by its base,
a box by its footprint on the ground), walls (their foot line) and named zones. Everything on the page is in pixels;
this module turns the scene into that (:func:`page_state`) and the page's edit back into the scene (:func:`save`).

**Measured ground points.** Where the camera was solved from the people walking through the video (calibration
format ``people``) and the layout is drawn in pixels, the user may also click ground features and type their
measured positions (x, y in metres, in axes of their choice); they go to ``calibration.points`` and refine the camera
(:mod:`vc.calibration.points_and_people`), and the page redraws the grid, horizon and plan through the refined one.
A layout in metres would move with the camera, so there the page takes no points.

**Which frame is written.** A scene drawn in pixels (``layout: {frame: image}``, what ``vc-scene init`` writes)
keeps its pixels. A metric scene (``frame: ground``) is shown projected through its camera and written back in
metres: an element the user changed is taken from its pixels onto the ground (:mod:`vc.scenes.pixel_layout`), one
left alone is written exactly as it was (a projection there and back would move it by rounding). A metric element
that cannot be shown (a point behind the camera) is listed, locked, and kept as it was.

**What is written.** ``scene.yaml`` and nothing else, and only its ``layout``, ``zones`` and ``calibration.points``
entries: the rest of the file keeps its text and comments (:func:`vc.scenes.loader.top_level_span`). The edited file
is first written beside the scene and loaded by the same loader as ``vc-scene check``, with its region plan; a bad
edit gets the loader's message, naming the field, and the scene file is not touched. A good one replaces it in one
rename.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import numpy as np
import shapely
import yaml
from pydantic import ValidationError

from vc.calibration.camera import Camera
from vc.errors import InputError
from vc.io import atomic_path
from vc.scenes.layout import Cylinder, Layout
from vc.scenes.loader import Scene, load_scene, read_scene_file, top_level_span
from vc.scenes.overlay import figure_lines, image_runs
from vc.scenes.pixel_layout import (
    PixelBox,
    PixelCylinder,
    PixelLayout,
    PixelWall,
    ground_points,
    obstacle_on_ground,
    wall_on_ground,
)
from vc.scenes.regions import Region, max_visible_distance, plan_regions, visible_ground

#: Grid lines of the ground are drawn this far apart (metres) ...
GRID_STEPS_M = (1.0, 2.0, 5.0, 10.0)
#: ... the finest step that draws at most this many lines across the shown ground.
MAX_GRID_LINES = 60
#: Metres of ground past the walkable area's bounds that the grid covers.
GRID_MARGIN_M = 5.0
#: Ground pixels the grid is sampled at along a line (metres), so that a distorting lens bends it.
GRID_SAMPLE_M = 0.25
#: Pixels beyond the image that points may lie at and still be shown and edited (share of the image's size).
PAGE_MARGIN = 0.5


def _pixels(array: np.ndarray) -> list[list[float]]:
    return [[round(float(u), 2), round(float(v), 2)] for u, v in np.asarray(array).reshape(-1, 2)]


def _shown(camera: Camera, points: np.ndarray) -> list[list[float]] | None:
    """The pixels of ground ``points`` ((N, 3) metres), or None when one cannot be shown on the page."""
    projection = camera.project(points)
    width, height = camera.size
    uv = projection.uv
    inside = projection.ok & (uv[:, 0] > -PAGE_MARGIN * width) & (uv[:, 0] < (1 + PAGE_MARGIN) * width) \
        & (uv[:, 1] > -PAGE_MARGIN * height) & (uv[:, 1] < (1 + PAGE_MARGIN) * height)
    return _pixels(uv) if inside.all() else None


def _on_ground(xy) -> np.ndarray:
    xy = np.asarray(xy, np.float64).reshape(-1, 2)
    return np.c_[xy, np.zeros(len(xy))]


def _elements(scene: Scene) -> dict:
    """The scene's layout and zones as the page edits them: pixels, each with its ``source`` index in the file."""
    camera, drawn = scene.camera, scene.drawn_layout
    locked: list[str] = []
    if drawn is not None:
        walkable = [{"points": polygon, "source": index} for index, polygon in enumerate(drawn.walkable)]
        obstacles = [{**obstacle.model_dump(exclude_none=True), "source": index}
                     for index, obstacle in enumerate(drawn.obstacles)]
        walls = [{**wall.model_dump(exclude_none=True), "source": index} for index, wall in enumerate(drawn.walls)]
    else:
        layout: Layout = scene.layout
        walkable, obstacles, walls = [], [], []
        seen = visible_ground(camera, max_visible_distance(camera, min(scene.priors.height_m),
                                                            scene.regions.min_person_px))
        for index, polygon in enumerate(layout.walkable):
            shown, clipped = _shown(camera, _on_ground(polygon)), False
            if shown is None:  # reaching past the view: the part the camera sees, which is all the planner keeps
                part = shapely.Polygon(polygon).intersection(seen)
                if isinstance(part, shapely.Polygon) and not part.is_empty:
                    shown, clipped = _shown(camera, _on_ground(np.asarray(part.exterior.coords)[:-1])), True
            if shown:
                walkable.append({"points": shown, "source": index, **({"clipped": True} if clipped else {})})
            else:
                locked.append(f"walkable {index}")
        for index, obstacle in enumerate(layout.obstacles):
            name = obstacle.name or f"obstacle {index}"
            if isinstance(obstacle, Cylinder):
                shown = _shown(camera, _on_ground(obstacle.base))
                entry = shown and {"type": "cylinder", "base": shown[0], "radius": obstacle.radius,
                                   "height": obstacle.height}
            else:
                shown = _shown(camera, _on_ground(obstacle.corners()[:4, :2]))
                entry = shown and {"type": "box", "footprint": shown, "height": obstacle.size[2],
                                   "bottom": obstacle.bottom}
            if entry:
                obstacles.append({**entry, **({"name": obstacle.name} if obstacle.name else {}), "source": index})
            else:
                locked.append(name)
        for index, wall in enumerate(layout.walls):
            shown = _shown(camera, _on_ground([wall.start, wall.end]))
            if shown:
                walls.append({"start": shown[0], "end": shown[1], "height": wall.height, "thickness": wall.thickness,
                              **({"name": wall.name} if wall.name else {}), "source": index})
            else:
                locked.append(wall.name or f"wall {index}")
    zones = []
    for index, zone in enumerate(scene.zones):
        shown = zone.polygon if zone.frame == "image" else _shown(camera, _on_ground(zone.polygon))
        if shown:
            zones.append({"name": zone.name, "frame": zone.frame, "points": shown, "source": index})
        else:
            locked.append(f"zone {zone.name}")
    return {"walkable": walkable, "obstacles": obstacles, "walls": walls, "zones": zones, "locked": locked}


def grid_lines(camera: Camera, layout: Layout) -> dict:
    """The ground grid in metres over the walkable area and a margin, as pixel polylines within the image, with its
    step."""
    x0, y0, x1, y1 = layout.walkable_area().bounds
    x0, y0, x1, y1 = x0 - GRID_MARGIN_M, y0 - GRID_MARGIN_M, x1 + GRID_MARGIN_M, y1 + GRID_MARGIN_M
    step = next((step for step in GRID_STEPS_M if max(x1 - x0, y1 - y0) / step <= MAX_GRID_LINES), GRID_STEPS_M[-1])
    lines = []
    for fixed_x in (True, False):
        low, high = (x0, x1) if fixed_x else (y0, y1)
        along = np.arange(y0 if fixed_x else x0, (y1 if fixed_x else x1) + GRID_SAMPLE_M, GRID_SAMPLE_M)
        for value in np.arange(math.ceil(low / step) * step, high + 1e-9, step):
            points = np.c_[np.full_like(along, value), along] if fixed_x else np.c_[along, np.full_like(along, value)]
            for run in image_runs(camera, _on_ground(points)):
                inside = camera.is_in_image(run)
                # the pieces of the run inside the image, each drawn on its own
                edges = np.flatnonzero(np.diff(np.r_[0, inside.astype(np.int8), 0]))
                for start, end in zip(edges[::2], edges[1::2], strict=True):
                    if end - start >= 2:
                        lines.append({"metres": round(float(value), 3), "axis": "x" if fixed_x else "y",
                                      "pixels": _pixels(run[start:end])})
    return {"step_m": step, "lines": lines}


def figures_at(camera: Camera, pixel: tuple[float, float], statures_m: tuple[float, ...]) -> dict:
    """Person figures of ``statures_m`` standing on the ground the ``pixel`` sees, as pixel polylines, with that
    ground point and each figure's height in pixels; ``ground`` None above the horizon."""
    hit = camera.ground_from_pixels(np.asarray([pixel], np.float64))
    if not hit.ok[0]:
        return {"ground": None, "figures": []}
    foot = hit.points[0]
    figures = []
    for stature in statures_m:
        lines = [_pixels(run) for line in figure_lines(camera, foot, stature) for run in image_runs(camera, line)]
        height_px = float(camera.person_pixel_height(foot[None], stature)[0])
        figures.append({"stature_m": stature, "height_px": round(height_px, 1), "lines": lines})
    return {"ground": [round(float(foot[0]), 3), round(float(foot[1]), 3)], "figures": figures}


def _region_entries(camera: Camera, regions: list[Region]) -> list[dict]:
    entries = []
    for region in regions:
        geometry = region.ground
        polygons = [geometry] if geometry.geom_type == "Polygon" else list(getattr(geometry, "geoms", []))
        outlines = [_pixels(run) for polygon in polygons if not polygon.is_empty
                    for run in image_runs(camera, _on_ground(np.asarray(polygon.exterior.segmentize(0.25).coords)),
                                          closed=True)]
        entries.append({"name": region.name, "crop": region.crop.to_list(), "input_size": list(region.input_size),
                        "person_px": [round(float(value), 1) for value in region.person_px], "outlines": outlines})
    return entries


def _points_refusal(spec, drawn_in_pixels: bool) -> str | None:
    """Why the page cannot take measured ground points for this scene, or None when it can: they refine a camera
    solved from people, and a layout in metres would move with the camera they change."""
    if spec.calibration is None or spec.calibration.format != "people":
        return "ground points refine a camera solved from people walking through a video (vc-scene init VIDEO)"
    if not drawn_in_pixels:
        return "ground points need the layout drawn in pixels (layout: {frame: image}): one in metres would move"
    return None


def _ground_points(spec) -> list[dict]:
    """The scene's measured ground points as the page edits them: a pixel and its ground position."""
    rows = (spec.calibration.points or []) if spec.calibration is not None else []
    return [{"pixel": [u, v], "x": x, "y": y, "source": index} for index, (u, v, x, y) in enumerate(rows)]


def _camera_entry(camera: Camera) -> dict:
    return {"focal_px": round(float(camera.fx), 1), "height_m": round(float(camera.center[2]), 3)}


def page_state(scene_path: Path) -> dict:
    """Everything the page draws for the scene as it is saved: the image size, the layout, zones and measured ground
    points in pixels, the statures, the grid, the horizon and the region plan."""
    scene = load_scene(scene_path)
    spec = read_scene_file(Path(scene_path))
    camera = scene.camera
    return {"scene": scene.name, "path": str(scene.path), "size": list(camera.size),
            "frame": "image" if scene.drawn_layout is not None else "ground",
            "statures_m": [float(value) for value in scene.priors.height_m], **_elements(scene),
            "points": _ground_points(spec), "points_refused": _points_refusal(spec, scene.drawn_layout is not None),
            "camera": _camera_entry(camera), "grid": grid_lines(camera, scene.layout),
            "horizon": _pixels(camera.horizon_pixels()), "regions": _region_entries(camera, plan_regions(scene))}


# ------------------------------------------------------------------------------------------------- the edit back


def _edited_layout(edit: dict, original: dict, camera: Camera, frame: str, path: Path) -> dict:
    """The ``layout`` entry the page's ``edit`` makes of the file's ``original`` one (both plain data)."""
    def kept(kind: str, element: dict):
        source = element.get("source")
        if element.get("edited") or source is None:
            return None
        entries = original.get(kind) or []
        if not isinstance(source, int) or not 0 <= source < len(entries):
            raise InputError(path, f"layout.{kind}", f"the page refers to entry {source}, which the file lacks")
        return entries[source]

    def validated(model, data: dict, field: str):
        try:
            return model.model_validate({key: value for key, value in data.items() if key not in ("source", "edited")})
        except ValidationError as error:
            first = error.errors(include_url=False)[0]
            where = ".".join(str(part) for part in (field, *first["loc"]))
            raise InputError(path, where, first["msg"].removeprefix("Value error, ")) from None

    layout: dict = {"frame": "image"} if frame == "image" else {}
    walkable = []
    for index, element in enumerate(edit.get("walkable", [])):
        field = f"layout.walkable.{index}"
        points = kept("walkable", element)
        if points is None:
            pixels = element.get("points") or []
            points = pixels if frame == "image" else ground_points(camera, pixels, field, path).round(4).tolist()
        walkable.append(points)
    def placed(kind: str, model_of, on_ground) -> list:
        """The ``kind`` entries: kept as they were, or validated from their pixels and placed in the frame."""
        entries = []
        for index, element in enumerate(edit.get(kind, [])):
            field = f"layout.{kind}.{index}"
            entry = kept(kind, element)
            if entry is None:
                drawn = validated(model_of(element), element, field)
                entry = drawn.model_dump(exclude_none=True) if frame == "image" \
                    else {key: value for key, value in on_ground(drawn, camera, field, path).items()
                          if value is not None}
            entries.append(entry)
        return entries

    obstacles = placed("obstacles", lambda element: PixelCylinder if element.get("type") == "cylinder" else PixelBox,
                       obstacle_on_ground)
    walls = placed("walls", lambda element: PixelWall, wall_on_ground)
    locked = {"walkable": [], "obstacles": [], "walls": []}
    for kind in locked:
        shown = {element.get("source") for element in edit.get(kind, []) if element.get("source") is not None}
        shown |= set(edit.get("removed", {}).get(kind, []))
        locked[kind] = [entry for index, entry in enumerate(original.get(kind) or []) if index not in shown]
    # a metric element the page could not show is kept as it was
    layout["walkable"] = walkable + locked["walkable"]
    layout["obstacles"] = obstacles + locked["obstacles"]
    layout["walls"] = walls + locked["walls"]
    return layout


def _edited_zones(edit: dict, original: list, camera: Camera, path: Path) -> list[dict]:
    zones = []
    for index, element in enumerate(edit.get("zones", [])):
        field = f"zones.{index}"
        source = element.get("source")
        if not element.get("edited") and isinstance(source, int) and 0 <= source < len(original):
            zones.append(original[source])
            continue
        frame = element.get("frame", "image")
        pixels = element.get("points") or []
        polygon = pixels if frame == "image" \
            else ground_points(camera, pixels, f"{field}.polygon", path).round(4).tolist()
        zones.append({"name": element.get("name", ""), **({"frame": "image"} if frame == "image" else {}),
                      "polygon": polygon})
    shown = {element.get("source") for element in edit.get("zones", [])} | set(edit.get("removed", {}).get("zones", []))
    return zones + [zone for index, zone in enumerate(original) if index not in shown]


def _edited_calibration(edit: dict, spec, original: dict, path: Path) -> dict:
    """The ``calibration`` entry with the page's measured ground points (``[u, v, x, y]`` rows; none: the key goes);
    InputError naming the point for a value that is not a number, or for points where the scene takes none."""
    if "points" not in edit:
        return original
    points = edit["points"]
    if points and (refused := _points_refusal(spec, isinstance(spec.layout, PixelLayout))):
        raise InputError(path, "calibration.points", refused)
    rows = []
    for index, element in enumerate(points):
        try:
            row = [float(value) for value in (*element.get("pixel", []), element.get("x"), element.get("y"))]
        except (TypeError, ValueError):
            row = []
        if len(row) != 4 or not all(math.isfinite(value) for value in row):
            raise InputError(path, f"calibration.points.{index}", "a point needs its pixel and its ground x, y in "
                                                                  "metres, as numbers")
        rows.append([round(value, 4) for value in row])
    calibration = {key: value for key, value in original.items() if key != "points"}
    return {**calibration, "points": rows} if rows else calibration


def _flow_dump(key: str, value) -> str:
    """``key: value`` as a block YAML entry whose innermost lists are written in flow style, one point a line."""
    return yaml.safe_dump({key: value}, sort_keys=False, default_flow_style=None, width=120)


def edited_text(scene_path: Path, edit: dict) -> str:
    """The scene file's text with its ``layout`` and ``zones`` replaced by the page's ``edit``; InputError naming the
    field when an edited element cannot be placed (a pixel above the horizon, a malformed shape)."""
    scene_path = Path(scene_path)
    text = scene_path.read_text()
    spec = read_scene_file(scene_path)
    scene = load_scene(scene_path)
    document = yaml.safe_load(text)
    frame = "image" if isinstance(spec.layout, PixelLayout) else "ground"
    layout = _edited_layout(edit, document.get("layout") or {}, scene.camera, frame, scene_path)
    zones = _edited_zones(edit, document.get("zones") or [], scene.camera, scene_path)
    edited = [("layout", layout), ("zones", zones)]
    calibration = _edited_calibration(edit, spec, document.get("calibration") or {}, scene_path)
    if calibration:  # none: the camera is inline, and takes no points
        edited.append(("calibration", calibration))
    for key, value in edited:
        if value == (document.get(key) or ([] if key == "zones" else {})):
            continue  # unchanged: its text and comments stay as they are
        span = top_level_span(text, key)
        if key == "zones" and not value:
            text = text if span is None else text[:span[0]] + text[span[1]:]
            continue
        block = _flow_dump(key, value)
        if span is None:
            text = text + ("" if text.endswith("\n") else "\n") + block
        else:
            text = text[:span[0]] + block + text[span[1]:]
    return text


def check(scene_path: Path, edit: dict) -> tuple[str, Scene, list[Region]]:
    """The edited scene's text, loaded and planned by the same code as ``vc-scene check`` from a file beside the
    scene (its relative paths resolve as the scene's do), which is then removed; InputError with the loader's
    message, naming ``scene_path``, for a bad edit."""
    scene_path = Path(scene_path).resolve()
    text = edited_text(scene_path, edit)
    handle, name = tempfile.mkstemp(prefix=f".{scene_path.name}.", suffix=".edit", dir=scene_path.parent)
    try:
        with os.fdopen(handle, "w") as file:
            file.write(text)
        try:
            scene = load_scene(name)
            regions = plan_regions(scene)
        except InputError as error:
            raise InputError(scene_path, error.field, error.reason) from None
    finally:
        Path(name).unlink(missing_ok=True)
    return text, scene, regions


def save(scene_path: Path, edit: dict) -> dict:
    """Check the page's ``edit`` (:func:`check`) and, only when it loads, replace ``scene.yaml`` with it in one
    rename; the page's new state (what it then shows)."""
    scene_path = Path(scene_path).resolve()
    text, _, _ = check(scene_path, edit)
    with atomic_path(scene_path) as temporary:
        temporary.write_text(text)
    return page_state(scene_path)


def preview(scene_path: Path, edit: dict) -> dict:
    """The region plan and grid the edit would give, without writing anything (the page's "check")."""
    _, scene, regions = check(scene_path, edit)
    return {"regions": _region_entries(scene.camera, regions), "grid": grid_lines(scene.camera, scene.layout),
            "horizon": _pixels(scene.camera.horizon_pixels()), "camera": _camera_entry(scene.camera),
            "walkable_area_m2": round(float(scene.layout.walkable_area().area), 2),
            "zones": [zone.name for zone in scene.zones]}

