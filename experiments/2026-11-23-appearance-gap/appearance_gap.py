"""How people look in the renders against how they look in the camera's frames: brightness, contrast with the
ground behind them, and colourfulness, measured the same way on both.

    python experiments/2026-11-23-appearance-gap/appearance_gap.py --dataset RENDERS --video V --gt GT.txt
        [--frames 1:400:10] [--out experiments/2026-11-23-appearance-gap/results] [--name pets09]

For every person (ground-truth boxes of the frames; label boxes of the renders, taller than 20 px) the centre
of the box — the middle 40 % of its width, 15–85 % of its height: torso and legs, little of what is around —
is compared with the same pixels of the empty background (the scene's background image; the region's crop of
it for the renders), in linear light through the scene's response: the person's median luminance, the log2
ratio of it over the background's there (contrast), and the median saturation ((max - min) / max of RGB).
Evaluation data only: nothing measured here feeds a render. Writes ``appearance_gap_<name>.json``,
``appearance_gap_<name>.md`` and ``appearance_gap_<name>.png`` (histograms of the contrast and the luminance).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vc.calibration.materials import luminance  # noqa: E402
from vc.deploy.frames import FrameRange, FrameSource  # noqa: E402
from vc.evaluation.mot import read_mot_boxes  # noqa: E402
from vc.io import read_image, write_json  # noqa: E402
from vc.render.plan import region_background  # noqa: E402
from vc.scenes.loader import load_scene  # noqa: E402
from vc.scenes.regions import plan_regions  # noqa: E402

#: The part of a box measured (fractions of its width and height): the body, little of the ground around it.
CENTRE_X, CENTRE_Y = (0.30, 0.70), (0.15, 0.85)
MIN_HEIGHT_PX = 20


def measure_people(image: np.ndarray, background: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """(N, 3): median luminance, log2 contrast with the background, median saturation per box (x, y, w, h) of
    linear images ``image`` and ``background``; boxes whose centre leaves the image are skipped."""
    rows = []
    height, width = image.shape[:2]
    for x, y, w, h in boxes:
        x0, x1 = int(x + CENTRE_X[0] * w), int(x + CENTRE_X[1] * w)
        y0, y1 = int(y + CENTRE_Y[0] * h), int(y + CENTRE_Y[1] * h)
        if h < MIN_HEIGHT_PX or x1 <= x0 or y1 <= y0 or x0 < 0 or y0 < 0 or x1 > width or y1 > height:
            continue
        person = image[y0:y1, x0:x1].reshape(-1, 3)
        behind = background[y0:y1, x0:x1].reshape(-1, 3)
        level, ground = np.median(luminance(person)), np.median(luminance(behind))
        saturation = np.median((person.max(axis=1) - person.min(axis=1)) / np.maximum(person.max(axis=1), 1e-4))
        rows.append((level, np.log2(max(level, 1e-4) / max(ground, 1e-4)), saturation))
    return np.array(rows).reshape(-1, 3)


def real_people(scene, video: Path, gt: Path, frames: str) -> np.ndarray:
    response = scene.camera_response().response
    background = response.decode(read_image(scene.image_path))
    corners = read_mot_boxes(gt)
    measured = []
    for frame in FrameSource(video, FrameRange.parse(frames)):
        boxes = corners.get(frame.number, np.zeros((0, 4)))
        measured.append(measure_people(response.decode(frame.image), background,
                                       np.c_[boxes[:, :2], boxes[:, 2:] - boxes[:, :2]]))
    return np.concatenate(measured)


def rendered_people(scene, dataset: Path, per_region: int) -> np.ndarray:
    response = scene.camera_response().response
    background = read_image(scene.image_path)
    measured = []
    for region in plan_regions(scene):
        behind = response.decode(region_background(background, region))
        count = 0
        for shard in sorted((dataset / region.name).glob("shard-*")):
            annotations = json.loads((shard / "annotations.json").read_text())
            for entry in annotations["images"]:
                if count >= per_region:
                    break
                boxes = np.array([a["bbox"] for a in annotations["annotations"] if a["image_id"] == entry["id"]])
                image = response.decode(read_image(shard / "images" / Path(entry["file_name"]).name))
                measured.append(measure_people(image, behind, boxes.reshape(-1, 4)))
                count += 1
    return np.concatenate(measured)


def summary(rows: np.ndarray) -> dict:
    quartiles = lambda column: [round(float(v), 4) for v in np.percentile(rows[:, column], [25, 50, 75])]  # noqa: E731
    return {"people": len(rows), "luminance_quartiles": quartiles(0), "contrast_log2_quartiles": quartiles(1),
            "saturation_quartiles": quartiles(2)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", type=Path, default=Path("examples/scenes/pets09_s2l1/scene.yaml"))
    parser.add_argument("--dataset", type=Path, required=True, help="a vc-render dataset of the scene")
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--gt", type=Path, required=True)
    parser.add_argument("--frames", default="1:400:10")
    parser.add_argument("--per-region", type=int, default=100, help="rendered samples measured per region")
    parser.add_argument("--name", default="pets09")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = parser.parse_args()
    scene = load_scene(args.scene)
    real, rendered = real_people(scene, args.video, args.gt, args.frames), rendered_people(scene, args.dataset,
                                                                                             args.per_region)
    manifest = json.loads((args.dataset / "manifest.json").read_text())
    result = {"scene": scene.name, "frames": args.frames, "dataset_lighting": manifest.get("lighting", {}).get(
        "illumination"), "real": summary(real), "rendered": summary(rendered)}
    write_json(args.out / f"appearance_gap_{args.name}.json", result)
    lines = ["| people | n | luminance (median, IQR) | contrast with the ground, log2 (median, IQR) | saturation |",
             "|---|---|---|---|---|"]
    for name in ("real", "rendered"):
        s = result[name]
        lum, con, sat = s["luminance_quartiles"], s["contrast_log2_quartiles"], s["saturation_quartiles"]
        lines.append(f"| {name} | {s['people']} | {lum[1]:.3f} ({lum[0]:.3f}–{lum[2]:.3f}) | "
                     f"{con[1]:+.2f} ({con[0]:+.2f} to {con[2]:+.2f}) | {sat[1]:.2f} |")
    (args.out / f"appearance_gap_{args.name}.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    for rows, label in ((real, "real frames"), (rendered, "renders")):
        left.hist(rows[:, 1], bins=40, range=(-8, 3), alpha=0.5, density=True, label=f"{label} ({len(rows)})")
        right.hist(np.log2(np.maximum(rows[:, 0], 1e-4)), bins=40, range=(-10, 0), alpha=0.5, density=True,
                   label=label)
    left.set(xlabel="person over ground behind it (log2 luminance)", ylabel="density", title="contrast")
    right.set(xlabel="person luminance (log2, linear light)", title="brightness")
    left.legend()
    figure.suptitle(f"{scene.name}: people in the renders against people in the frames")
    figure.tight_layout()
    figure.savefig(args.out / f"appearance_gap_{args.name}.png", dpi=110)


if __name__ == "__main__":
    main()
