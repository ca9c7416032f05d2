"""Where should a person's peak be drawn so that people in groups keep one each? (frozen experiment, issue 57 item 2)

    PYTHONPATH=../.. python anchors.py separation RENDERS REGION
    PYTHONPATH=../.. python anchors.py train RUN RENDERS REGION -o OUT
    PYTHONPATH=../.. python anchors.py peaks RUN RENDERS REGION [--checkpoint PT --visible]

``separation``: on the region's held-out renders, for each asked-for person overlapping another, the distance (in
their heights) to the nearest other person's anchor, for three anchors: the amodal centre (today's, half the stature
above the feet), the centre of the visible box, and the visible pixels' centroid snapped to the nearest visible pixel.
Also how often each anchor's cell (stride 4) is owned by the person (the centre offsets there point to their centre).

``train``: the region's network trained as RUN's checkpoint was (same config, renders and seed), except that its centre
map and fine centre map are drawn at each person's visible centroid (``--anchor visible``); the centre offsets still
point from each cell to the person's amodal centre, so that the offset at a peak says where the person's centre is.
With ``--hidden-weight K`` the centre map's squared error under a partly hidden person's Gaussian weighs up to
1 + K x the share of them hidden (seen: visible pixels over :data:`SILHOUETTE_FILL` of their amodal box); with
``--steps-factor F`` it trains F times as many steps; ``--centre-sigma`` sets the peaks' width, ``--offset-unit U``
draws the offsets in U cells (a head's offset in heights says nothing of the person's size where heads lie on the
horizon), ``--size-unit U`` has the fine map's first channel learn each person's log height in U cells over their
pixels (a size to read at a head). Writes OUT/checkpoints/REGION.pt.

``peaks``: on the region's held-out renders, each asked-for person overlapping another against the centre map's
3x3 local maxima: the strongest within 0.1 of their height of their anchor (amodal centre, or with ``--visible``
their visible centroid) and nearer it than anyone else's, at thresholds 0.1 / 0.2 / 0.3 (the decoder's), by the
share of them seen; ``--on-train``: on 200 of the renders it was trained on instead.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np
import torch

import vc.model.codec as codec
import vc.model.data as data_module
import vc.model.loss as loss_module
from vc.deploy.heatmaps import CENTRE_CHANNEL, FINE_CENTRE_CHANNELS, MASK_CHANNEL, input_to_cells
from vc.evaluation.metrics import grouped
from vc.evaluation.renders import asked_for
from vc.model.trainer import RegionTrainer, load_checkpoint
from vc.render.dataset import open_region, read_sample

STRIDE = 4
#: The share of a person's amodal box their silhouette fills (COCO pedestrians: about half): visible pixels over this
#: share of the box are the share of them seen.
SILHOUETTE_FILL = 0.45
#: The anchors' names in :func:`anchors_of`.
ANCHOR_KEYS = {"centre": "amodal centre", "visible": "visible centroid", "head": "head"}
#: COCO's first five keypoints: nose, eyes, ears.
HEAD_KEYPOINTS = 5


def visible_centroid(instances: np.ndarray, instance_id: int) -> np.ndarray | None:
    """The centroid of the person's visible pixels, moved to the nearest of them (x, y), or None if none is."""
    rows, columns = np.nonzero(instances == instance_id)
    if not len(rows):
        return None
    mean = np.array([columns.mean(), rows.mean()])
    nearest = np.argmin((columns - mean[0]) ** 2 + (rows - mean[1]) ** 2)
    return np.array([columns[nearest], rows[nearest]], float)


def head_point(annotation: dict) -> np.ndarray:
    """The middle of the person's labelled nose, eyes and ears (seen or hidden), where their head is."""
    face = np.reshape(annotation["keypoints"], (-1, 3))[:HEAD_KEYPOINTS]
    labelled = face[face[:, 2] > 0]
    return labelled[:, :2].mean(axis=0) if len(labelled) else np.array(annotation["center"], float)


def anchors_of(annotation: dict, instances: np.ndarray) -> dict[str, np.ndarray]:
    x, y, width, height = annotation["bbox"]
    centroid = visible_centroid(instances, annotation["instance_id"])
    return {"amodal centre": np.array(annotation["center"], float), "head": head_point(annotation),
            "visible box centre": np.array([x + width / 2, y + height / 2]),
            "visible centroid": np.array(annotation["center"], float) if centroid is None else centroid}


def owned(instances: np.ndarray, point: np.ndarray, instance_id: int) -> bool:
    """Whether the stride cell holding ``point`` is covered most by ``instance_id`` (its offsets are theirs)."""
    row, column = int(point[1] // STRIDE), int(point[0] // STRIDE)
    cell = instances[row * STRIDE:(row + 1) * STRIDE, column * STRIDE:(column + 1) * STRIDE]
    if not cell.size:
        return False
    ids, counts = np.unique(cell[cell > 0], return_counts=True)
    return bool(len(ids)) and int(ids[np.argmax(counts)]) == instance_id


def separation(renders: Path, region: str) -> None:
    data = open_region(renders, region, 0.1)
    nearest: dict[str, list[float]] = {}
    own_cell: dict[str, list[bool]] = {}
    for sample in data.held_out:
        _, instances = read_sample(sample)
        size = (instances.shape[1], instances.shape[0])
        annotations = [a for a in sample.annotations if a.get("center") is not None]
        if len(annotations) < 2:
            continue
        boxes = np.array([[a["amodal_bbox"][0], a["amodal_bbox"][1], a["amodal_bbox"][0] + a["amodal_bbox"][2],
                           a["amodal_bbox"][1] + a["amodal_bbox"][3]] for a in annotations])
        heights = boxes[:, 3] - boxes[:, 1]
        points = [anchors_of(a, instances) for a in annotations]
        in_group = grouped(boxes)
        for person, annotation in enumerate(annotations):
            if not (in_group[person] and asked_for(annotation, size)):
                continue
            for name in points[person]:
                others = np.array([points[o][name] for o in range(len(annotations)) if o != person])
                distance = np.hypot(*(others - points[person][name]).T).min() / heights[person]
                nearest.setdefault(name, []).append(float(distance))
                own_cell.setdefault(name, []).append(owned(instances, points[person][name],
                                                           annotation["instance_id"]))
    for name, values in nearest.items():
        values = np.array(values)
        print(f"{region} {name}: {len(values)} people overlapping another; nearest other's within 0.1 / 0.15 heights "
              f"{np.mean(values < 0.1):.3f} / {np.mean(values < 0.15):.3f}, median {np.median(values):.3f}; "
              f"its cell theirs {np.mean(own_cell[name]):.3f}")


def _offsets_to_amodal_centres(offsets, annotations, coverages, stride) -> None:
    """The codec's centre offsets, drawn to each person's amodal centre whatever their "center" (the peak) says; with
    :data:`OFFSET_UNIT_CELLS` set, in that many cells instead of each person's height."""
    amodal = [{**annotation, "center": annotation.get("amodal_center", annotation.get("center"))}
              for annotation in annotations]
    if OFFSET_UNIT_CELLS[0] is not None:
        amodal = [{**annotation, "amodal_bbox": [0.0, 0.0, 0.0, OFFSET_UNIT_CELLS[0] * stride]}
                  for annotation in amodal]  # the codec divides by the height it reads here
    shares = {id(moved): coverages[id(annotation)] for moved, annotation in zip(amodal, annotations, strict=True)
              if id(annotation) in coverages}
    _DRAW_OFFSETS(offsets, amodal, shares, stride)


def _shifted_keeping(annotation: dict, dx: float, dy: float) -> dict:
    """The training window's annotation (:func:`vc.model.data.shifted`) with the amodal centre and the share seen."""
    moved = _SHIFTED(annotation, dx, dy)
    if annotation.get("amodal_center") is not None:
        moved["amodal_center"] = [annotation["amodal_center"][0] + dx, annotation["amodal_center"][1] + dy]
    if "seen" in annotation:
        moved["seen"] = annotation["seen"]
    return moved


def _encode_weighted(annotations, instances, config):
    """The codec's targets and one more map: the centre loss's weight, 1 + HIDDEN_WEIGHT x (1 - share seen) under each
    partly hidden person's centre Gaussian (maximum where they overlap)."""
    targets = _ENCODE(annotations, instances, config)
    weight = np.ones((1, *targets.shape[1:]), np.float32)
    for annotation in annotations:
        hidden = 1.0 - min(annotation.get("seen", 1.0), 1.0)
        if annotation.get("center") is None or hidden <= 0.0 or HIDDEN_WEIGHT[0] == 0.0:
            continue
        gaussian = np.zeros_like(weight)
        sigma = max(config.centre_sigma * annotation["amodal_bbox"][3] / config.stride, config.min_sigma_cells)
        codec._draw_gaussians(gaussian, np.array([0]), input_to_cells([annotation["center"]], config.stride), sigma)
        weight = np.maximum(weight, 1.0 + HIDDEN_WEIGHT[0] * hidden * gaussian)
    if SIZE_UNIT_CELLS[0] is not None:
        _draw_sizes(targets[SIZE_CHANNEL], annotations, instances, config.stride)
    return np.concatenate([targets, weight])


def _draw_sizes(sizes: np.ndarray, annotations: list[dict], instances: np.ndarray, stride: int) -> None:
    """Over each cell a person covers most: log(their amodal height / SIZE_UNIT_CELLS cells); 0 elsewhere."""
    sizes[:] = 0.0
    people = [annotation for annotation in annotations if annotation.get("instance_id") is not None]
    if not people:
        return
    rows, columns = sizes.shape
    shares = np.stack([(instances == annotation["instance_id"]).reshape(rows, stride, columns, stride)
                       .mean(axis=(1, 3)) for annotation in people])
    owner, owned = shares.argmax(axis=0), shares.max(axis=0) > 0
    logs = np.log(np.array([annotation["amodal_bbox"][3] / stride for annotation in people])
                  / SIZE_UNIT_CELLS[0])
    sizes[owned] = logs[owner[owned]]


def _weighted_terms(prediction, targets):
    """:func:`vc.model.loss.heatmap_terms` with the detection term weighed by the targets' extra map (and, with a
    size map in the fine map's first channel, that channel's mask-weighed L1 in the offsets' term instead)."""
    if targets.shape[1] != prediction.shape[1] + 1:
        return _TERMS(prediction, targets)
    weight, targets = targets[:, -1], targets[:, :-1]
    terms = _TERMS(prediction, targets)
    terms["detection"] = (weight * (prediction[:, CENTRE_CHANNEL] - targets[:, CENTRE_CHANNEL]).square()).mean()
    if SIZE_UNIT_CELLS[0] is not None:
        fine = slice(SIZE_CHANNEL + 1, FINE_CENTRE_CHANNELS.stop)
        terms["fine_centre"] = (prediction[:, fine] - targets[:, fine]).square().mean()
        error = (prediction[:, SIZE_CHANNEL] - targets[:, SIZE_CHANNEL]).abs() * targets[:, MASK_CHANNEL]
        terms["centre_offsets"] = terms["centre_offsets"] + error.mean()
    return terms


_DRAW_OFFSETS = codec._draw_centre_offsets
_SHIFTED = data_module.shifted
_ENCODE = codec.encode
_TERMS = loss_module.heatmap_terms
HIDDEN_WEIGHT = [0.0]
#: The centre offsets' unit in cells (None: each person's height, as the codec draws them).
OFFSET_UNIT_CELLS: list[float | None] = [None]
#: With a unit (cells), the fine map's first channel learns each person's log height in it over their cells instead.
SIZE_UNIT_CELLS: list[float | None] = [None]
SIZE_CHANNEL = FINE_CENTRE_CHANNELS.start


def train(run: Path, renders: Path, region: str, out: Path, anchor: str, hidden_weight: float,
          steps_factor: float, centre_sigma: float | None, offset_unit: float | None,
          size_unit: float | None = None) -> None:
    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    config = dataclasses.replace(checkpoint.config, steps=round(checkpoint.config.steps * steps_factor))
    if centre_sigma is not None:
        config = dataclasses.replace(config, codec=dataclasses.replace(config.codec, centre_sigma=centre_sigma))
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    moved = 0
    for sample in data.train:  # before the loader's workers fork
        _, instances = read_sample(sample)
        for annotation in sample.annotations:
            if annotation.get("center") is None:
                continue
            x, y, width, height = annotation["amodal_bbox"]
            annotation["seen"] = np.count_nonzero(instances == annotation["instance_id"]) / (
                SILHOUETTE_FILL * max(width * height, 1.0))
            annotation["amodal_center"] = annotation["center"]
            centroid = visible_centroid(instances, annotation["instance_id"])
            if anchor == "visible" and centroid is not None:
                annotation["center"] = centroid.tolist()
                moved += 1
            elif anchor == "head":
                annotation["center"] = head_point(annotation).tolist()
                moved += 1
    print(f"{moved} people's peaks drawn at their {anchor} point; hidden weight {hidden_weight}", flush=True)
    HIDDEN_WEIGHT[0] = hidden_weight
    OFFSET_UNIT_CELLS[0] = offset_unit
    SIZE_UNIT_CELLS[0] = size_unit
    codec._draw_centre_offsets = _offsets_to_amodal_centres
    data_module.shifted = _shifted_keeping
    data_module.encode = _encode_weighted
    loss_module.heatmap_terms = _weighted_terms
    trainer = RegionTrainer(data, config, out, renders, device=torch.device("cpu"), workers=1)
    trainer.train()


def peaks(run: Path, renders: Path, region: str, weights: Path | None, anchor: str, on_train: bool) -> None:
    from vc.deploy.decode import local_maxima
    from vc.deploy.heatmaps import cells_to_input
    from vc.model.network import ScenePoseNet

    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    net = ScenePoseNet(checkpoint.config.network)
    net.load_state_dict(load_checkpoint(weights).content["model"] if weights else checkpoint.content["model"])
    net.eval()
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    values, visibility = [], []
    for sample in data.train[:200] if on_train else data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        _, strengths, cells = local_maxima(maps[CENTRE_CHANNEL][None], 0.05)
        points = cells_to_input(np.asarray(cells, float), checkpoint.config.codec.stride).reshape(-1, 2)
        strengths = np.asarray(strengths, float)
        size = (instances.shape[1], instances.shape[0])
        annotations = [a for a in sample.annotations if a.get("center") is not None]
        if len(annotations) < 2:
            continue
        key = ANCHOR_KEYS[anchor]
        anchors = np.array([anchors_of(a, instances)[key] for a in annotations])
        boxes = np.array([[a["amodal_bbox"][0], a["amodal_bbox"][1], a["amodal_bbox"][0] + a["amodal_bbox"][2],
                           a["amodal_bbox"][1] + a["amodal_bbox"][3]] for a in annotations])
        heights = boxes[:, 3] - boxes[:, 1]
        in_group = grouped(boxes)
        owner = np.full(len(points), -1)
        for index, point in enumerate(points):
            distance = np.hypot(*(anchors - point).T) / heights
            nearest = int(np.argmin(distance))
            if distance[nearest] <= 0.1:
                owner[index] = nearest
        for person, annotation in enumerate(annotations):
            if in_group[person] and asked_for(annotation, size):
                values.append(float(strengths[owner == person].max(initial=0.0)))
                seen = np.count_nonzero(instances == annotation["instance_id"])
                visibility.append(seen / (SILHOUETTE_FILL * boxes[person, 2:].__sub__(boxes[person, :2]).prod()))
    values, visibility = np.array(values), np.array(visibility)
    for low, high in ((0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 9)):
        chosen = (visibility >= low) & (visibility < high)
        print(f"  seen {low}-{high}: {chosen.sum()} people, a peak of their own (0.3) "
              f"{np.mean(values[chosen] >= 0.3):.3f}")
    print(f"{region} {ANCHOR_KEYS[anchor]} {weights or 'shipped'}, "
          f"{'200 training' if on_train else 'held-out'} renders: {len(values)} people "
          f"overlapping another; a peak of their own at 0.1 / 0.2 / 0.3: "
          + " / ".join(f"{np.mean(values >= t):.3f}" for t in (0.1, 0.2, 0.3)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("separation", "train", "peaks"))
    parser.add_argument("paths", type=Path, nargs="+", help="separation: RENDERS; train: RUN RENDERS")
    parser.add_argument("region")
    parser.add_argument("-o", "--out", type=Path)
    parser.add_argument("--checkpoint", type=Path, help="peaks: weights to read instead of RUN's")
    parser.add_argument("--visible", action="store_true", help="peaks: anchors at the visible centroid")
    parser.add_argument("--anchor", choices=tuple(ANCHOR_KEYS),
                        help="the peak's point (train: default visible; peaks: default centre)")
    parser.add_argument("--centre-sigma", type=float, help="train: the peak's Gaussian sigma, in heights")
    parser.add_argument("--offset-unit", type=float,
                        help="train: the centre offsets in this many cells, not in each person's height")
    parser.add_argument("--size-unit", type=float,
                        help="train: the fine map's first channel learns log(height / this many cells) instead")
    parser.add_argument("--hidden-weight", type=float, default=0.0,
                        help="train: the centre loss weighs a partly hidden person's peak 1 + this x the share hidden")
    parser.add_argument("--steps-factor", type=float, default=1.0, help="train: this many times RUN's steps")
    parser.add_argument("--on-train", action="store_true", help="peaks: on 200 training renders, not the held-out")
    args = parser.parse_args()
    if args.what == "separation":
        separation(args.paths[0], args.region)
    elif args.what == "train":
        train(args.paths[0], args.paths[1], args.region, args.out, args.anchor or "visible", args.hidden_weight,
              args.steps_factor,
              args.centre_sigma, args.offset_unit, args.size_unit)
    else:
        peaks(args.paths[0], args.paths[1], args.region, args.checkpoint,
              "visible" if args.visible else args.anchor or "centre", args.on_train)


if __name__ == "__main__":
    main()
