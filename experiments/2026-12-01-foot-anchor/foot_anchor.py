"""Does a person's foot point keep people in groups apart where their centre does not? (frozen experiment)

    PYTHONPATH=../.. python foot_anchor.py real                          # TUD-Stadtmitte's boxes: nearest other
    PYTHONPATH=../.. python foot_anchor.py train RUN RENDERS r0 -o OUT   # the region's network, centre map at the feet
    PYTHONPATH=../.. python foot_anchor.py peaks RUN RENDERS r0 --anchor centre|foot [--checkpoint PT]

``real``: for each annotated person overlapping another (IoU >= 0.1), the distance to the nearest other person's box
centre, foot point (bottom middle) and head point (top middle), in their heights, on both halves of TUD-Stadtmitte
and PETS09's dev frames.

``train``: the region's network trained as RUN's checkpoint was (same config, same renders, same seed), except that
its "centre" map, offsets and fine centre map are drawn at each person's foot point (the renders' ``foot`` label)
instead of half the stature above it. Writes OUT/checkpoints/REGION.pt.

``peaks``: on the region's held-out renders, the local maxima (3x3) of the centre map (``--fine``: of the fine centre
map, twice the resolution) at or above 0.3, against
each asked-for person's anchor: a person has a peak of their own when a peak lies within 0.1 of their height of
their anchor and no other person's anchor is nearer it. Reported for the people overlapping another and those
apart, with the peaks near nobody.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch

from vc.deploy.decode import local_maxima
from vc.deploy.heatmaps import CENTRE_CHANNEL, FINE_CENTRE_CHANNELS, FINE_FACTOR, cells_to_input, fine_centre_map
from vc.evaluation.metrics import grouped
from vc.evaluation.renders import asked_for
from vc.model.network import ScenePoseNet
from vc.model.trainer import RegionTrainer, load_checkpoint
from vc.render.dataset import open_region, read_sample

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
#: Each camera's ground truth (MOT text) and its halves (first, last frame).
CAMERAS = {"TUD-Stadtmitte": (DATA / "tud_stadtmitte" / "gt_world.txt", ((1, 90), (91, 179))),
           "PETS09": (DATA / "pets09_s2l1" / "gt_dev_frames_0001-0400.txt", ((1, 200), (201, 400)))}
PEAK_THRESHOLD = 0.3  # the decoder's centre_threshold
OWN_PEAK_REACH = 0.1  # person heights


def real() -> None:
    for camera, (path, halves) in CAMERAS.items():
        _nearest_points(camera, np.loadtxt(path, delimiter=","), halves)


def _nearest_points(camera: str, rows: np.ndarray, halves: tuple[tuple[int, int], ...]) -> None:
    for first, last in halves:
        nearest: dict[str, list[float]] = {"centre": [], "foot": [], "head": []}
        for frame in range(first, last + 1):
            annotated = rows[rows[:, 0] == frame]
            boxes = np.c_[annotated[:, 2:4], annotated[:, 2:4] + annotated[:, 4:6]]
            middle = (boxes[:, 0] + boxes[:, 2]) / 2
            points = {"centre": np.c_[middle, (boxes[:, 1] + boxes[:, 3]) / 2], "foot": np.c_[middle, boxes[:, 3]],
                      "head": np.c_[middle, boxes[:, 1]]}
            for person in np.flatnonzero(grouped(boxes)):
                others = np.delete(np.arange(len(boxes)), person)
                for name, point in points.items():
                    distance = np.hypot(*(point[others] - point[person]).T) / annotated[person, 5]
                    nearest[name].append(float(distance.min()))
        for name, values in nearest.items():
            values = np.array(values)
            print(f"{camera} frames {first}-{last}, {len(values)} people overlapping another: nearest other {name} "
                  f"10/25/50 % {np.percentile(values, [10, 25, 50]).round(3).tolist()} heights, "
                  f"within 0.15: {np.mean(values < 0.15):.3f}")


def train(run: Path, renders: Path, region: str, out: Path) -> None:
    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    for sample in data.train:  # before the loader's workers fork: the codec draws "centre" where the feet are
        for annotation in sample.annotations:
            if annotation.get("center") is not None and annotation.get("foot") is not None:
                annotation["center"] = annotation["foot"]
    trainer = RegionTrainer(data, checkpoint.config, out, renders, device=torch.device("cpu"), workers=1)
    trainer.train()


def peaks(run: Path, renders: Path, region: str, anchor: str, weights: Path | None,
          reach: float = OWN_PEAK_REACH, fine: bool = False) -> None:
    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    config = checkpoint.config
    net = ScenePoseNet(config.network)
    net.load_state_dict(load_checkpoint(weights).content["model"] if weights else checkpoint.content["model"])
    net.eval()
    data = open_region(renders, region, config.held_out_fraction)
    counts = {"overlapping another": [0, 0], "apart": [0, 0]}
    peaks_total = peaks_near_nobody = feet_outside = 0
    nearest_other: list[float] = []
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        if fine:
            _, _, cells = local_maxima(fine_centre_map(maps[FINE_CENTRE_CHANNELS])[None], PEAK_THRESHOLD)
            points = cells_to_input(np.asarray(cells, float), config.codec.stride // FINE_FACTOR).reshape(-1, 2)
        else:
            _, _, cells = local_maxima(maps[CENTRE_CHANNEL][None], PEAK_THRESHOLD)
            points = cells_to_input(np.asarray(cells, float), config.codec.stride).reshape(-1, 2)
        size = (instances.shape[1], instances.shape[0])
        annotations = [a for a in sample.annotations if a.get("center") is not None]
        if not annotations:
            peaks_total += len(points)
            peaks_near_nobody += len(points)
            continue
        anchors = np.array([a["foot" if anchor == "foot" else "center"] for a in annotations], float)
        heights = np.array([a["amodal_bbox"][3] for a in annotations], float)
        boxes = np.array([[a["amodal_bbox"][0], a["amodal_bbox"][1], a["amodal_bbox"][0] + a["amodal_bbox"][2],
                           a["amodal_bbox"][1] + a["amodal_bbox"][3]] for a in annotations])
        in_group = grouped(boxes)
        owner = np.full(len(points), -1)
        for index, point in enumerate(points):
            distance = np.hypot(*(anchors - point).T) / heights
            nearest = int(np.argmin(distance))
            if distance[nearest] <= reach:
                owner[index] = nearest
        peaks_total += len(points)
        peaks_near_nobody += int(np.sum(owner < 0))
        for person, annotation in enumerate(annotations):
            if not asked_for(annotation, size):
                continue
            kind = "overlapping another" if in_group[person] else "apart"
            counts[kind][0] += 1
            counts[kind][1] += bool(np.any(owner == person))
            if in_group[person]:
                others = np.delete(anchors, person, axis=0)
                nearest_other.append(float((np.hypot(*(others - anchors[person]).T) / heights[person]).min()))
            foot_x, foot_y = annotation["foot"]
            feet_outside += not (-0.5 <= foot_x <= size[0] - 0.5 and -0.5 <= foot_y <= size[1] - 0.5)
    for kind, (people, own) in counts.items():
        print(f"{region}, anchor {anchor}, {'fine' if fine else 'coarse'} map, reach {reach}: {kind}: {people} people, "
              f"{own / people:.3f} with a peak of their own")
    separations = np.array(nearest_other)
    print(f"  overlapping another: the nearest other person's {anchor} within 0.15 of their height for "
          f"{np.mean(separations < 0.15):.3f} (median {np.median(separations):.3f})")
    print(f"  {peaks_total} peaks, {peaks_near_nobody} near nobody; {feet_outside} of the people have their feet "
          f"outside the input")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("real", "train", "peaks"))
    parser.add_argument("run", type=Path, nargs="?")
    parser.add_argument("renders", type=Path, nargs="?")
    parser.add_argument("region", nargs="?")
    parser.add_argument("-o", "--out", type=Path)
    parser.add_argument("--anchor", choices=("centre", "foot"), default="centre")
    parser.add_argument("--checkpoint", type=Path, help="peaks: weights to read instead of RUN's")
    parser.add_argument("--fine", action="store_true", help="peaks: of the fine centre map (twice the resolution)")
    parser.add_argument("--reach", type=float, default=OWN_PEAK_REACH, help="peaks: a peak's reach, in heights")
    args = parser.parse_args()
    if args.what == "real":
        real()
    elif args.what == "train":
        train(args.run, args.renders, args.region, args.out)
    else:
        peaks(args.run, args.renders, args.region, args.anchor, args.checkpoint, args.reach, args.fine)


if __name__ == "__main__":
    main()
