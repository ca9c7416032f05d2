"""A first scene for a new camera from what its installer has: its video (or one image) and a calibration, or a
handful of measured ground points (``vc-scene init``).

1. **Background**: the image as given, or the per-pixel temporal median of the video or folder of frames
   (:mod:`vc.scenes.background`); with a ground truth of boxes (``--mot-world``), the median of each pixel over
   the frames where no person covers it, so that people who stood still leave no ghost.
2. **Camera**: a calibration file as given (copied beside the scene), or solved from measured ground points
   (:mod:`vc.calibration.ground_points`) and written as ``camera.yaml`` for review. Points may also come from a
   MOTChallenge-style ground truth that carries each person's ground position (``frame, id, left, top, width,
   height, conf, x, y, z``): the bottom centre of each box not cut by the image's bottom border is a foot pixel,
   and (x, y) its ground point. With none of these, the camera is solved from the people who walk through the
   video (:mod:`vc.calibration.walkers`, :mod:`vc.calibration.from_people`), with a focal length given or solved;
   a focal length the people cannot tell (a level camera) is refused by name. Their sightings are written to
   ``walkers.json`` and drawn in ``walkers.png``; the scene's calibration is that file (format ``people``).
   Measured points given with a video are solved together with the people walking through it
   (:mod:`vc.calibration.points_and_people`: the points win where they tell, the people fill in what they leave
   free; two points then suffice), and the scene names them beside the people (``calibration.points``), where
   ``vc-scene edit`` adds more; where the people cannot be used, the points alone, which then need four, and the
   summary says why.
3. **Walkable ground**, drawn in pixels (``layout: {frame: image}``) for the user to trim: the image area whose
   pixels see the ground where a person of the prior's smallest stature stands at least ``min_person_px`` tall
   (the region planner's limit) and no taller than the image (closer, only their legs would be in view: an eye-
   level camera sees the ground at its feet with people many times the frame's height), its largest connected
   part outlined.
4. ``scene.yaml`` (lighting and effects ``auto``), then the scene is loaded like any other (so it is valid) and
   its overlay drawn.
"""

from __future__ import annotations

import os
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import yaml

from vc.calibration.camera import Camera
from vc.calibration.from_people import MAX_FOCAL_SPREAD, MIN_PROFILE_RISE, PeopleCalibration, solve
from vc.calibration.ground_points import (
    MIN_POINTS,
    GroundCalibration,
    calibrate_from_ground_points,
    read_ground_points,
    write_opencv_yaml,
)
from vc.calibration.points_and_people import calibrate_from_points_and_people
from vc.calibration.readers import read_calibration
from vc.calibration.walkers import Sighting, walkers_in_video
from vc.deploy.frames import IMAGE_SUFFIXES, FrameRange
from vc.errors import InputError
from vc.evaluation.mot import read_mot_boxes, read_mot_world
from vc.io import read_image, write_image, write_json
from vc.scenes.background import BackgroundResult, median_background
from vc.scenes.schema import Priors, RegionPlanSpec
from vc.scenes.walker_overlay import draw_walkers

#: The walkable outline is simplified to within this many pixels.
OUTLINE_TOLERANCE_PX = 2.0
#: The walkable area is found on a grid of this pitch (px), then outlined at full resolution.
GRID_PX = 4
#: Calibration file formats by suffix, for ``--calibration`` without ``--format``.
FORMAT_BY_SUFFIX = {".xml": "tsai-xml", ".ci": "towncentre-ci", ".yaml": "opencv", ".yml": "opencv",
                    ".json": "opencv", ".csv": "ground-points", ".txt": "homography"}


@dataclass(frozen=True)
class StarterScene:
    """What ``vc-scene init`` wrote, and how well the camera fits its points."""

    scene_path: Path
    background_path: Path
    camera: Camera
    calibration_source: str
    fit: GroundCalibration | None  # None: a calibration file was given
    walkable_px: list[list[float]]
    ground_points_path: Path | None = None  # points taken from a ground truth, for review
    background: BackgroundResult | None = None  # None: the image was given
    people: PeopleCalibration | None = None  # the camera as solved from people walking through the video
    people_unused: str | None = None  # why the people did not refine the points, when they did not

    def to_dict(self) -> dict:
        result = {"scene": self.scene_path.name, "background": self.background_path.name,
                  "calibration": self.calibration_source, "camera": self.camera.to_dict(),
                  "camera_height_m": round(float(self.camera.center[2]), 3),
                  "walkable_px_vertices": len(self.walkable_px)}
        if self.fit is not None:
            result["fit"] = {key: value for key, value in self.fit.to_dict().items() if key != "points"}
            result["points"] = len(self.fit.errors_px)
        if self.people is not None:
            result["people"] = self.people.to_dict()
        if self.people_unused is not None:
            result["people_unused"] = self.people_unused
        if self.background is not None:
            result["background_median"] = {key: value for key, value in self.background.to_dict().items()
                                           if key != "frame_indices"}
        return result


def scene_name(folder: Path) -> str:
    """A scene name (letters, digits, ``_.-``) from the output folder's name."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", folder.resolve().name).strip("_") or "camera"


def ground_points_from_mot(path: Path, image_height: int, margin_px: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """Foot pixels (N, 2) and ground points (N, 2 m) from a ground truth with world positions
    (:func:`vc.evaluation.mot.read_mot_world`): the bottom centre of every box that ends at least ``margin_px``
    above the image's bottom border."""
    boxes, ground = read_mot_world(path)
    inside = boxes[:, 3] <= image_height - margin_px
    if not inside.any():
        raise InputError(path, "", "no box with a ground position whose bottom is inside the image")
    feet = np.column_stack([(boxes[:, 0] + boxes[:, 2]) / 2 - 0.5, boxes[:, 3] - 0.5])  # outer edges -> centres
    return feet[inside], ground[inside]


def walkable_outline(camera: Camera, height_m: float, min_person_px: float) -> list[list[float]]:
    """The image area where the ground is seen with a ``height_m`` person at least ``min_person_px`` and at most
    the image's height tall, as one polygon in pixels (its largest connected part)."""
    width, height = camera.size
    columns, rows = np.meshgrid(np.arange(0, width, GRID_PX, dtype=np.float64),
                                np.arange(0, height, GRID_PX, dtype=np.float64))
    pixels = np.stack([columns, rows], axis=-1).reshape(-1, 2)
    hit = camera.ground_from_pixels(pixels)
    tall = np.zeros(len(pixels), bool)
    person_px = camera.person_pixel_height(hit.points[hit.ok], height_m)
    tall[hit.ok] = (person_px >= min_person_px) & (person_px <= height)
    grid = tall.reshape(rows.shape).astype(np.uint8)
    mask = cv2.resize(grid, (width, height), interpolation=cv2.INTER_NEAREST)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=4)
    if count < 2:
        raise InputError(None, "camera", "the camera sees no ground where people would be visible: is it looking at "
                                         "the sky, or is the calibration upside down?")
    largest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    contours, _ = cv2.findContours((labels == largest).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    outline = cv2.approxPolyDP(max(contours, key=cv2.contourArea), OUTLINE_TOLERANCE_PX, True)[:, 0, :]
    return outline.astype(float).tolist()


def camera_from_walkers(video: Path, background: np.ndarray, folder: Path, focal_px: float | None,
                        frames: FrameRange | None, progress: bool) -> PeopleCalibration:
    """The camera solved from the people walking alone through ``video``'s ``frames``; their sightings written to
    ``folder/walkers.json`` and drawn in ``folder/walkers.png``. InputError when the people cannot tell the focal
    length and none is given."""
    sightings = walkers_in_video(video, background, frames, progress)
    people = solve(np.array([s.head for s in sightings]), np.array([s.foot for s in sightings]),
                   np.array([s.track for s in sightings]), (background.shape[1], background.shape[0]), focal_px)
    if not people.focal_observable:
        worse = " and ".join(f"{ratio - 1:+.0%}" for ratio in people.profile)
        raise InputError(video, "--focal", f"the people walking through this view cannot tell the camera's focal "
                                           f"length: it varies by {people.focal_spread_share:.0%} over resamples of "
                                           f"them (at most {MAX_FOCAL_SPREAD:.0%}), and half or twice it explains "
                                           f"them {worse} worse (at least {MIN_PROFILE_RISE:+.0%}); a camera at eye "
                                           f"level, or people who all walk at one depth, do this: give --focal in "
                                           f"pixels, or --points")
    write_json(folder / "walkers.json", {"size": list(people.camera.size), "people": people.to_dict(),
                                         "sightings": [_sighting_dict(sighting, bool(kept)) for sighting, kept
                                                       in zip(sightings, people.inliers, strict=True)]})
    write_image(folder / "walkers.png", draw_walkers(background, sightings, people))
    return people


def _people_beside_points(source: Path, median: BackgroundResult | None, background: np.ndarray, folder: Path,
                          focal_px: float | None, frames: FrameRange | None, progress: bool,
                          wanted: bool) -> tuple[PeopleCalibration | None, str | None]:
    """The people walking through ``source`` solved to refine measured points, or None and why not (one image,
    not wanted, too few people, a focal length they cannot tell)."""
    if not wanted:
        return None, "--no-people was given"
    if median is None:
        return None, "one image shows no one walking"
    try:
        return camera_from_walkers(source, background, folder, focal_px, frames, progress), None
    except InputError as refused:
        return None, f"the people could not be used ({refused.reason})"


def _sighting_dict(sighting: Sighting, kept: bool) -> dict:
    return {"frame": sighting.frame, "track": sighting.track, "head": [round(v, 1) for v in sighting.head],
            "foot": [round(v, 1) for v in sighting.foot], "kept": kept}


def _background(source: Path, destination: Path, progress: bool, people: Path | None, frames: FrameRange | None
                ) -> tuple[BackgroundResult | None, np.ndarray]:
    """The background image written to ``destination``, and how it was made from a video's (or folder's)
    ``frames``, if it was; ``people``: a ground truth whose boxes are left out of the median."""
    if source.is_file() and source.suffix.lower() in IMAGE_SUFFIXES:
        image = read_image(source)
        write_image(destination, image)
        return None, image
    result = median_background(source, progress=progress, people=None if people is None else read_mot_boxes(people),
                               frames=frames)
    write_image(destination, result.image)
    return result, result.image


def make_starter_scene(source: Path, folder: Path, points: Path | None = None, calibration: Path | None = None,
                       calibration_format: str | None = None, mot_world: Path | None = None,
                       focal_px: float | None = None, progress: bool = True, name: str | None = None,
                       frames: FrameRange | None = None, with_people: bool = True) -> StarterScene:
    """Write ``folder/scene.yaml`` with its background and camera (see the module docstring); the scene is
    ``name``d after the folder unless given (a staging folder stands in for the one it becomes). With no points,
    calibration or ground truth, the camera is solved from the people walking through the video; with points and
    a video, from both unless ``with_people`` is False. ``frames``: the frames of the video (or folder) read for
    both (default: all)."""
    given = [option for option in (points, calibration, mot_world) if option is not None]
    if len(given) > 1:
        raise InputError(None, "--points", "give at most one of --points, --calibration or --mot-world")
    if not with_people and points is None:
        raise InputError(None, "--no-people", "goes with --points only: without points the camera comes from a "
                                              "calibration file, a ground truth's feet, or the people alone")
    folder.mkdir(parents=True, exist_ok=True)
    median, image = _background(Path(source), folder / "background.png", progress, mot_world, frames)
    size = (image.shape[1], image.shape[0])
    fit, points_path, people, people_unused = None, None, None, None
    if not given:
        people = camera_from_walkers(Path(source), image, folder, focal_px, frames, progress)
        camera = people.camera
        reference = {"format": "people", "path": "walkers.json", "response": "auto"}
        source_text = f"{people.tracks} people walking through it"
    elif calibration is not None:
        calibration_format = calibration_format or FORMAT_BY_SUFFIX.get(calibration.suffix.lower())
        if calibration_format is None:
            raise InputError(calibration, "--format", "cannot tell the calibration's format from its name: give "
                                                      "--format")
        camera = read_calibration(calibration, calibration_format, size, None, focal_px)
        copied = folder / f"calibration{calibration.suffix.lower()}"
        if calibration.resolve() != copied.resolve():
            shutil.copyfile(calibration, copied)
        reference = {"format": calibration_format, "path": copied.name, "size": list(size), "response": "auto"}
        if focal_px is not None:
            reference["focal_px"] = focal_px
        source_text = f"{calibration_format} file {calibration.name}"
    else:
        if mot_world is not None:
            image_points, ground_points = ground_points_from_mot(mot_world, size[1])
            points_path = folder / "ground_points.csv"
            points_path.write_text("u,v,x,y\n" + "".join(f"{u:.2f},{v:.2f},{x:.4f},{y:.4f}\n" for (u, v), (x, y)
                                                         in zip(image_points, ground_points, strict=True)))
            source_text = f"{len(image_points)} feet of {mot_world.name}"
            fit = calibrate_from_ground_points(image_points, ground_points, size, focal_px, mot_world)
        else:
            image_points, ground_points = read_ground_points(points)
            source_text = f"{len(image_points)} ground points of {points.name}"
            people, people_unused = _people_beside_points(Path(source), median, image, folder, focal_px, frames,
                                                          progress, with_people)
            if people is not None:
                fit = calibrate_from_points_and_people(image_points, ground_points, people, points)
                source_text += f" and {people.tracks} people walking through it"
            else:
                if len(image_points) < MIN_POINTS:
                    raise InputError(points, "", f"{len(image_points)} points solve a camera only with the people "
                                                 f"walking through a video, and {people_unused}: measure "
                                                 f"{MIN_POINTS} or more")
                fit = calibrate_from_ground_points(image_points, ground_points, size, focal_px, points)
        camera = fit.camera
        if people is not None:  # the scene keeps the people and the points, so that the editor can add points
            reference = {"format": "people", "path": "walkers.json", "response": "auto",
                         "points": [[round(float(value), 4) for value in (*pixel, *metres)]
                                    for pixel, metres in zip(fit.image_points, fit.ground_points, strict=True)]}
        else:
            write_opencv_yaml(camera, folder / "camera.yaml")
            reference = {"format": "opencv", "path": "camera.yaml", "response": "auto"}
    priors, plan = Priors(), RegionPlanSpec()
    walkable = walkable_outline(camera, priors.height_m[0], plan.min_person_px)
    document = {"name": name or scene_name(folder), "image": "background.png"}
    if median is not None:
        document["video"] = os.path.relpath(Path(source).resolve(), folder.resolve())
    document.update({"calibration": reference,
                     "layout": {"frame": "image", "walkable": [[[round(u, 1), round(v, 1)] for u, v in walkable]],
                                "obstacles": [], "walls": []},
                     "lighting": "auto", "effects": "auto", "regions": "auto"})
    scene_path = folder / "scene.yaml"
    header = (f"# A starting scene made by vc-scene init from {Path(source).name} and {source_text}.\n"
              "# The walkable polygon is every pixel that sees ground where people are tall enough to detect: trim\n"
              "# it to where people can walk, and add obstacles (box footprints or cylinder bases, in pixels) and\n"
              "# walls that hide people. Check overlay.png: the figures must stand on the ground at people's size.\n"
              "# Say who walks there under priors: (docs/scenes.md), e.g. priors: {clothing: winter,\n"
              "# m2_per_person: 10} for coats on a busy pavement.\n")
    scene_path.write_text(header + yaml.safe_dump(document, sort_keys=False, width=120, default_flow_style=None))
    return StarterScene(scene_path, folder / "background.png", camera, source_text, fit, walkable, points_path,
                        median, people, people_unused)
