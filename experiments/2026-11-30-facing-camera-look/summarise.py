"""The tables of this experiment's README from its results (frozen, issue 57 item 4).

    python experiments/2026-11-30-facing-camera-look/summarise.py results/variants.jsonl WALK_DIR > results/summary.md

WALK_DIR holds walk_or_look.py's ``walk_{pets,tud}{0,1,2}_{half}.npy``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HALVES = {"pets": ("1", "201"), "tud": ("1", "91")}
# walk_or_look.py's columns
(FRAME, TRACK, SPEED, ERROR, ACROSS, COUNT, LOOK, NETWORK, MOTION, YOLO, HEIGHT, GROWTH, GROWTH_ERROR) = range(13)


def variants(path: Path) -> str:
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    lines = ["| variant | renders (compile seed) | weights | held-out renders | real people, choosing half |",
             "|---|---|---|---|---|"]
    for row in rows:
        if "variant" not in row:
            continue
        camera = "tud" if row["renders"].startswith("tud") else "pets"
        jitter = "" if row["renders"].endswith("_j0") else ", two jittered boxes a person"
        wardrobe = {"w0": ", renders in the winter wardrobe", "o0": ", renders with open coats (open_coat.patch)"}.get(
            row["renders"][-5:-3], "")
        lines.append(f"| {row['variant']}{jitter}{wardrobe} | {row['renders'][:-3]} | {row['weights']:,} | "
                     f"{row['renders_held_out']:.3f} | {row[f'real_{camera}']:.3f} |")
    for row in rows:
        if "weights" in row and isinstance(row["weights"], str):
            camera = "tud" if "tud" in row["weights"] else "pets"
            lines.append(f"| {row['weights']}: full frame / frame at the renders' scale | | | | "
                         f"{row[f'real_{camera}']:.3f} / {row[f'real_{camera}_scaled']:.3f} |")
    return "\n".join(lines)


def _rows(walks: Path, camera: str, half: str) -> np.ndarray:
    return np.concatenate([np.load(walks / f"walk_{camera}{seed}_{half}.npy") for seed in (0, 1, 2)])


def walk_or_look(walks: Path) -> str:
    lines = ["| camera, half | people (3 seeds) | the facing model | the walk, where there is one | today's rule | "
             "walk where z >= 1, else the model | z >= 2 | z >= 4 |", "|---|---|---|---|---|---|---|---|"]
    speed_lines = ["| camera (choosing) | vertical foot speed (heights/s) | people | the walk right | "
                   "the model right |", "|---|---|---|---|---|"]
    z_lines = ["| camera (choosing) | the walk's significance (z) | people | the walk right | the model right |",
               "|---|---|---|---|---|"]
    growth_lines = ["| camera, half | people today's rule leaves to the walk | of them, boxes growing or "
                    "shrinking faster than 0.4 log height/s | the walk right | the model right |",
                    "|---|---|---|---|---|"]
    for camera, halves in HALVES.items():
        for half in halves:
            rows = _rows(walks, camera, half)
            yolo, speed = rows[:, YOLO], rows[:, SPEED]
            has = (rows[:, COUNT] >= 4) & (speed != 0)
            walk, look = np.where(speed > 0, 1, -1), np.where(rows[:, LOOK] < 0, 1, -1)
            z = np.abs(speed) / rows[:, ERROR]
            walked = has & ((z >= 2) | (np.abs(rows[:, NETWORK]) < 0.3))
            today = np.where(walked, walk, look)
            fast = walked & (np.abs(rows[:, GROWTH]) > 0.4)
            right = (f"{np.mean(walk[fast] == yolo[fast]):.3f} | {np.mean(look[fast] == yolo[fast]):.3f} |"
                     if fast.any() else "– | – |")
            growth_lines.append(f"| {camera} {half} | {walked.sum()} | {fast.sum()} | {right}")
            rules = [np.where(has & (z >= k), walk, look) for k in (1, 2, 4)]
            lines.append(f"| {camera} {half} | {len(rows)} | {np.mean(look == yolo):.3f} | "
                         f"{np.mean(walk[has] == yolo[has]):.3f} | {np.mean(today == yolo):.3f} | "
                         + " | ".join(f"{np.mean(rule == yolo):.3f}" for rule in rules) + " |")
            if half != halves[0]:
                continue
            for low, high in ((0, 2), (2, 4), (4, 8), (8, np.inf)):
                inside = has & (z >= low) & (z < high)
                walk_right, look_right = np.mean(walk[inside] == yolo[inside]), np.mean(look[inside] == yolo[inside])
                z_lines.append(f"| {camera} | {low}-{high} | {inside.sum()} | {walk_right:.3f} | {look_right:.3f} |")
            for low, high in ((0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.4), (0.4, np.inf)):
                inside = has & (np.abs(speed) >= low) & (np.abs(speed) < high)
                speed_lines.append(f"| {camera} | {low}-{high} | {inside.sum()} | "
                                   f"{np.mean(walk[inside] == yolo[inside]):.3f} | "
                                   f"{np.mean(look[inside] == yolo[inside]):.3f} |")
    return "\n\n".join("\n".join(table) for table in (lines, speed_lines, z_lines, growth_lines))


if __name__ == "__main__":
    print("## The facing model's variants\n\n" + variants(Path(sys.argv[1])) + "\n\n## The walk or the model\n\n"
          + walk_or_look(Path(sys.argv[2])))
