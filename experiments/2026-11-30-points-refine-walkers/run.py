"""Do measured ground points and the people walking through the view make a better camera together than either
alone? (issue 60: "measured points still win where given, and can refine it"; frozen)

    PYTHONPATH=. python experiments/2026-11-30-points-refine-walkers/run.py \
        --out experiments/2026-11-30-points-refine-walkers/results

PETS09's people are found in each half of its dev frames (1-200 and 201-400, every frame) and solved alone
(``vc.calibration.from_people.solve``). The points are every subset of n of the eight features in
``examples/scenes/pets09_s2l1/ground_points.csv`` (whose ground positions come from the Tsai calibration), each
with an installer's errors drawn anew: 1.5 px in the image, 5 cm on the tape. Each camera is compared with the Tsai
calibration: focal length, tilt and height.
"""

from __future__ import annotations

import argparse
import itertools
import json
from pathlib import Path

import numpy as np

from vc.calibration.from_people import pose_of, solve
from vc.calibration.ground_points import calibrate_from_ground_points, read_ground_points
from vc.calibration.points_and_people import calibrate_from_points_and_people
from vc.calibration.walkers import walkers_in_video
from vc.deploy.frames import FrameRange
from vc.errors import InputError
from vc.scenes.background import median_background
from vc.scenes.loader import load_scene

ROOT = Path(__file__).resolve().parents[2]
PETS = ROOT / "examples" / "scenes" / "pets09_s2l1"
VIDEO = ROOT.parent / "shared" / "data" / "pets09_s2l1" / "vtest.avi"
HALVES = {"frames 1-200": FrameRange(1, 200, 1), "frames 201-400": FrameRange(201, 400, 1)}
CLICK_PX, TAPE_M = 1.5, 0.05
POINT_COUNTS = (2, 3, 4, 5, 6, 8)
DRAWS = {8: 30}  # draws of noise per subset; 3 unless named here


def errors(camera, truth: dict) -> list[float]:
    pose = pose_of(camera)
    return [round(100 * (pose["focal_px"] / truth["focal_px"] - 1), 3), round(pose["tilt_deg"] - truth["tilt_deg"], 3),
            round(100 * (pose["height_m"] / truth["height_m"] - 1), 3)]


def people_of(frames: FrameRange):
    background = median_background(VIDEO, progress=False, frames=frames).image
    sightings = walkers_in_video(VIDEO, background, frames, False)
    return solve(np.array([s.head for s in sightings]), np.array([s.foot for s in sightings]),
                 np.array([s.track for s in sightings]), (background.shape[1], background.shape[0]))


def trials(people, image, ground, truth, rng) -> list[dict]:
    rows = []
    for count in POINT_COUNTS:
        for subset in itertools.combinations(range(len(image)), count):
            for _ in range(DRAWS.get(count, 3)):
                pixels = image[list(subset)] + rng.normal(0.0, CLICK_PX, (count, 2))
                metres = ground[list(subset)] + rng.normal(0.0, TAPE_M, (count, 2))
                row = {"points": count, "subset": list(subset)}
                try:
                    row["points_alone"] = errors(calibrate_from_ground_points(pixels, metres, people.camera.size)
                                                 .camera, truth)
                except InputError as refused:
                    row["points_alone"] = None
                    row["points_alone_refused"] = refused.reason
                both = errors(calibrate_from_points_and_people(pixels, metres, people).camera, truth)
                if people.focal_observable:
                    row["combined"] = both
                else:  # as vc-scene init does: people whose focal length is refused do not refine the points
                    row["combined"] = row["points_alone"] if count >= 4 else None
                    row["refused_people_used"] = both
                rows.append(row)
    return rows


def summary_line(values: list[list[float] | None]) -> str:
    solved = np.abs(np.array([value for value in values if value is not None])).reshape(-1, 3)
    refused = sum(value is None for value in values)
    if not len(solved):
        return f"— | — | — | {refused} of {len(values)}"
    median, high = np.median(solved, axis=0), np.percentile(solved, 90, axis=0)
    return (f"{median[0]:.1f} % ({high[0]:.1f}) | {median[1]:.2f}° ({high[1]:.2f}) | {median[2]:.1f} % ({high[2]:.1f})"
            f" | {refused} of {len(values)}")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    truth = pose_of(load_scene(PETS / "scene.yaml").camera)
    image, ground = read_ground_points(PETS / "ground_points.csv")
    lines = ["# Points and people together against either alone (PETS09, against the Tsai calibration)", "",
             "Median absolute error (90th percentile in brackets); refused: no camera solved.", ""]
    with (args.out / "trials.jsonl").open("w") as handle:
        for half, frames in HALVES.items():
            people = people_of(frames)
            alone = errors(people.camera, truth)
            lines += [f"## People of {half}: {people.tracks} people", "",
                      f"The people alone: focal {alone[0]:+.1f} %, tilt {alone[1]:+.2f}°, height {alone[2]:+.1f} % "
                      f"(spread {people.spread['focal_px']:.0f} px, {people.spread['tilt_deg']:.2f}°, "
                      f"{people.spread['height_m']:.2f} m)"
                      + ("." if people.focal_observable else
                         f"; their focal length is refused (spread {people.focal_spread_share:.0%}, half and twice "
                         f"it fit {', '.join(f'{r - 1:+.0%}' for r in people.profile)} worse), so `vc-scene init` "
                         f"uses the points alone."), "",
                      "| points | camera from | focal | tilt | height | refused |", "|---|---|---|---|---|---|"]
            rows = trials(people, image, ground, truth, np.random.default_rng(0))
            for row in rows:
                handle.write(json.dumps({"people": half, **row}) + "\n")
            for count in POINT_COUNTS:
                chosen = [row for row in rows if row["points"] == count]
                if count >= 4:
                    lines.append(f"| {count} | points alone | {summary_line([r['points_alone'] for r in chosen])} |")
                lines.append(f"| {count} | points and people (`vc-scene init`) | "
                             f"{summary_line([r['combined'] for r in chosen])} |")
                if not people.focal_observable:
                    lines.append(f"| {count} | points and the refused people (not what `init` does) | "
                                 f"{summary_line([r['refused_people_used'] for r in chosen])} |")
            lines.append("")
    (args.out / "summary.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
