"""Where calibration from walkers fails: the solver (``vc.calibration.from_people.solve``) on people drawn through
known cameras, under the conditions issue 60 names (few people, one direction of walking, a camera looking straight
down) and a camera at eye level (frozen).

    PYTHONPATH=. python experiments/2026-11-30-where-walker-calibration-fails/run.py --out DIR [--draws 5]

The reference camera is PETS09's: 768x576, focal length 1190 px, 7 m up, looking down 16.5 degrees. Each condition
changes one thing. People: statures 1.70 +- 0.07 m, one in ten a child of 1.2 m, walking 1.3 m/s for 12 sightings
(5 a second) in their own direction, 5 to 45 m ahead and within the view; heads and feet seen with 1.5 px of noise
(what the drawn walkers' blobs show). Per condition, ``--draws`` sets of people; for each, the solution's error
against the camera and the bootstrap spread the solver reports (30 resamples). Writes ``DIR/conditions.jsonl`` and
``DIR/summary.md``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from vc.calibration.from_people import camera_of, pose_of, solve
from vc.errors import InputError

SIZE = (768, 576)
REFERENCE = {"focal_px": 1190.0, "tilt_deg": 16.5, "roll_deg": 0.0, "height_m": 7.0}
NOISE_PX = 1.5


def people(camera, count: int, rng: np.random.Generator, one_line: bool) -> tuple[np.ndarray, ...]:
    """Heads, feet and tracks of ``count`` walkers in ``camera``'s view; ``one_line``: all walk along one line
    across the view at one depth, the same way."""
    heads, feet, tracks = [], [], []
    person = 0
    line_depth = rng.uniform(12.0, 25.0)
    while person < count:
        stature = 1.2 if rng.random() < 0.1 else float(rng.normal(1.70, 0.07))
        if one_line:
            start, heading = np.array([rng.uniform(-8.0, 4.0), line_depth]), 0.0
        else:
            start, heading = np.array([rng.uniform(-15.0, 15.0), rng.uniform(5.0, 45.0)]), rng.uniform(0, 2 * np.pi)
        path = start + np.outer(np.arange(12) * 0.26, [np.cos(heading), np.sin(heading)])
        seen = camera.project(np.r_[np.c_[path, np.zeros(12)], np.c_[path, np.full(12, stature)]]).uv
        foot, head = seen[:12], seen[12:]
        inside = (np.isfinite(foot).all(axis=1) & np.isfinite(head).all(axis=1)
                  & (np.minimum(foot, head) >= 3).all(axis=1) & (foot[:, 0] < SIZE[0] - 3) & (head[:, 0] < SIZE[0] - 3)
                  & (np.maximum(foot[:, 1], head[:, 1]) < SIZE[1] - 3) & (foot[:, 1] - head[:, 1] >= 0.05 * SIZE[1]))
        if inside.sum() < 3:
            continue
        heads.append(head[inside] + rng.normal(0, NOISE_PX, (inside.sum(), 2)))
        feet.append(foot[inside] + rng.normal(0, NOISE_PX, (inside.sum(), 2)))
        tracks.append(np.full(inside.sum(), person))
        person += 1
    return np.concatenate(heads), np.concatenate(feet), np.concatenate(tracks)


CONDITIONS = {
    "reference (30 people)": {},
    "8 people": {"count": 8},
    "15 people": {"count": 15},
    "60 people": {"count": 60},
    "one line, one way": {"one_line": True},
    "tilt 2 deg": {"tilt_deg": 2.0, "height_m": 2.5},
    "tilt 5 deg": {"tilt_deg": 5.0, "height_m": 3.0},
    "tilt 45 deg": {"tilt_deg": 45.0, "height_m": 12.0},
    "tilt 70 deg": {"tilt_deg": 70.0, "height_m": 15.0},
    "tilt 85 deg (straight down)": {"tilt_deg": 85.0, "height_m": 15.0},
}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--draws", type=int, default=5)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, change in CONDITIONS.items():
        pose = {**REFERENCE, **{k: v for k, v in change.items() if k in REFERENCE}}
        camera = camera_of(SIZE, pose["focal_px"], pose["tilt_deg"], pose["roll_deg"], pose["height_m"])
        for draw in range(args.draws):
            rng = np.random.default_rng(1000 * draw + 7)
            heads, feet, tracks = people(camera, change.get("count", 30), rng, change.get("one_line", False))
            try:
                solved = solve(heads, feet, tracks, SIZE, bootstrap=30, seed=draw)
            except InputError as error:
                rows.append({"condition": name, "draw": draw, "refused": str(error)})
                continue
            got = pose_of(solved.camera)
            rows.append({"condition": name, "draw": draw, "sightings": len(heads),
                         "focal_error": got["focal_px"] / pose["focal_px"] - 1,
                         "tilt_error_deg": got["tilt_deg"] - pose["tilt_deg"],
                         "height_error": got["height_m"] / pose["height_m"] - 1,
                         "focal_spread": solved.focal_spread_share,
                         "tilt_spread_deg": solved.spread["tilt_deg"],
                         "height_spread": solved.spread["height_m"] / pose["height_m"],
                         "focal_observable": solved.focal_observable})
            print(json.dumps(rows[-1]), flush=True)
    with open(args.out / "conditions.jsonl", "w") as handle:
        handle.writelines(json.dumps(row) + "\n" for row in rows)
    lines = ["| condition | focal error | its spread | tilt error | its spread | height error | its spread | "
             "focal refused |", "|---|---|---|---|---|---|---|---|"]
    for name in CONDITIONS:
        mine = [row for row in rows if row["condition"] == name and "refused" not in row]
        if not mine:
            lines.append(f"| {name} | refused | | | | | | |")
            continue

        def median(key: str, rows=mine) -> float:
            return float(np.median([abs(row[key]) for row in rows]))

        refused = sum(not row["focal_observable"] for row in mine)
        lines.append(f"| {name} | {100 * median('focal_error'):.1f} % | {100 * median('focal_spread'):.1f} % | "
                     f"{median('tilt_error_deg'):.2f} deg | {median('tilt_spread_deg'):.2f} deg | "
                     f"{100 * median('height_error'):.1f} % | {100 * median('height_spread'):.1f} % | "
                     f"{refused} of {len(mine)} |")
    (args.out / "summary.md").write_text(
        f"Median over {args.draws} draws of the absolute error and of the bootstrap spread the solver reports "
        "(run.py).\n\n" + "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
