"""One peak, two people: the person behind read from the peak of the person in front (frozen experiment, issue 57
item 2).

    PYTHONPATH=../.. python second_person.py pairs RUN RENDERS REGION
    PYTHONPATH=../.. python second_person.py train RUN RENDERS REGION -o OUT
    PYTHONPATH=../.. python second_person.py measure RUN RENDERS REGION [--checkpoint PT] [--threshold T ...]
    PYTHONPATH=../.. python second_person.py added RUN RENDERS REGION --checkpoint PT [--threshold T]
    PYTHONPATH=../.. python second_person.py score RUN RENDERS REGION --checkpoint PT

The people today's far-band network misses in groups stand behind a found person, within 0.15 of their height of
that person's centre, under one peak (decisions 0033, 0034; ``../2026-12-03-second-look/``). CrowdDet (Chu et al.,
CVPR 2020) lets one proposal predict a set of people for that reason. Here each centre peak also predicts the person
hidden behind it: three more maps after the layout's (:data:`BEHIND_CHANNELS`): a score, a Gaussian at the centre of
each person P who has someone behind them (as wide as P's centre Gaussian), and, under it, the (x, y) from P's centre
to that person's centre, in P's heights.

Who is behind P (:func:`behind_of`): another person the evaluation asks for (at least half their height seen), whose
feet lie higher in the image than P's (further from the camera), whose full box overlaps P's (IoU >= 0.1) and whose
centre lies within :data:`BEHIND_REACH` of P's height of P's centre; of several, the least seen.

``pairs``: how many held-out people overlapping another have such a person in front of them, and, of those today's
network (RUN's checkpoint) misses, how many do (the most this formulation can recover).
``train``: the region's network trained as RUN's checkpoint was (same config, renders and seed) with the three maps
(their loss: the score's squared error beside the centre map's, the offsets' L1 weighed by the score's target beside
the centre offsets'). Writes OUT/checkpoints/REGION.pt.
``measure``: the held-out renders decoded as the deployment decoder does, and with the people behind added: for each
strong peak whose score map reads at least T there, a person at the offset's end unless a peak already lies within
:data:`SAME_PERSON` of their expected height of it. AP50, people overlapping another found, detections.
``added``: the people the behind maps add on the held-out renders (those not among the people decoded without them),
matched or not, and what the unmatched ones lie on, by their best IoU with an annotated person: >= 0.5 with one
already found (a second box for them: is anyone behind their front person, found or not?), >= 0.5 with one the
evaluation ignores, 0.3-0.5 (beside someone) or none.
"""

from __future__ import annotations

import argparse
import dataclasses
import threading
from collections import Counter
from pathlib import Path

import numpy as np
import torch

import vc.deploy.decode as decoding
import vc.model.codec as codec
import vc.model.config as config_module
import vc.model.data as data_module
import vc.model.held_out as held_out
import vc.model.loss as loss_module
from vc.calibration.camera import camera_from_dict
from vc.deploy.decode import DecodeConfig
from vc.deploy.heatmaps import FINE_CHANNELS, input_to_cells
from vc.evaluation.metrics import evaluate, grouped
from vc.evaluation.renders import MIN_VISIBLE_HEIGHT, asked_for, image_result
from vc.model.codec import expected_height_map
from vc.model.network import ScenePoseNet
from vc.model.trainer import RegionTrainer, load_checkpoint
from vc.render.dataset import open_region, read_sample

#: The three maps after the fine centre map's: the score, then the offset's x and y.
BEHIND = FINE_CHANNELS
BEHIND_CHANNELS = FINE_CHANNELS + 3
#: How far (P's heights) the centre of the person behind P may lie from P's: 0.5 takes in everyone TUD-Stadtmitte's
#: far band loses in groups (they stand within 0.15) and a person half a body beside.
BEHIND_REACH = 0.5
#: Amodal boxes overlapping at least this much (the evaluation's "overlapping another", metrics.grouped).
OVERLAP_IOU = 0.1
#: Under a score's Gaussian, the offsets are drawn where it is at least this (the cells the decoder reads at a peak).
OFFSET_CORE = 0.5
#: An added person this close (their expected heights) to a peak already decoded is that peak's person.
SAME_PERSON = [0.1]
#: The share of a person's amodal box their silhouette fills (as ../2026-12-01-visible-anchor/anchors.py).
SILHOUETTE_FILL = 0.45


def _xyxy(box: list[float]) -> np.ndarray:
    x, y, width, height = box
    return np.array([x, y, x + width, y + height], float)


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    width = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    height = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    inter = width * height
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def behind_of(annotations: list[dict], instances: np.ndarray, seen_below: float = np.inf) -> list[int | None]:
    """For each annotation, the index of the person behind them (see the module docstring), or None; with
    ``seen_below``, only people less seen than that count as behind (the others find a peak of their own)."""
    centred = [i for i, a in enumerate(annotations) if a.get("center") is not None]
    seen = {i: np.count_nonzero(instances == annotations[i]["instance_id"])
            / (SILHOUETTE_FILL * max(annotations[i]["amodal_bbox"][2] * annotations[i]["amodal_bbox"][3], 1.0))
            for i in centred}
    result: list[int | None] = [None] * len(annotations)
    for front in centred:
        a = annotations[front]
        box = _xyxy(a["amodal_bbox"])
        height = box[3] - box[1]
        candidates = []
        for other in centred:
            b = annotations[other]
            other_box = _xyxy(b["amodal_bbox"])
            if (other == front or other_box[3] >= box[3] or seen[other] >= seen_below
                    or b["bbox"][3] < MIN_VISIBLE_HEIGHT * b["amodal_bbox"][3]
                    or _iou(box, other_box) < OVERLAP_IOU
                    or np.hypot(b["center"][0] - a["center"][0], b["center"][1] - a["center"][1])
                    > BEHIND_REACH * height):
                continue
            candidates.append((seen[other], other))
        if candidates:
            result[front] = min(candidates)[1]
    return result


# ---- training: the three maps drawn, learned and kept through the training windows

def _channels(self) -> int:
    return BEHIND_CHANNELS if self.fine_centre else _CHANNELS.fget(self)


def _shifted_keeping(annotation: dict, dx: float, dy: float) -> dict:
    moved = _SHIFTED(annotation, dx, dy)
    behind = annotation.get("behind_center")
    moved["behind_center"] = None if behind is None else [behind[0] + dx, behind[1] + dy]
    return moved


def _encode_behind(annotations, instances, config):
    """The codec's maps with the three behind maps filled (the codec leaves them 0)."""
    targets = _ENCODE(annotations, instances, config)
    score, offsets = targets[BEHIND:BEHIND + 1], targets[BEHIND + 1:BEHIND + 3]
    for annotation in annotations:
        behind = annotation.get("behind_center")
        if annotation.get("center") is None or behind is None:
            continue
        height_px = codec.person_height_px(annotation)
        sigma = max(config.centre_sigma * height_px / config.stride, config.min_sigma_cells)
        gaussian = np.zeros_like(score)
        codec._draw_gaussians(gaussian, np.array([0]), input_to_cells([annotation["center"]], config.stride), sigma)
        core = (gaussian[0] >= OFFSET_CORE) & (gaussian[0] >= score[0])
        offsets[0][core] = (behind[0] - annotation["center"][0]) / height_px
        offsets[1][core] = (behind[1] - annotation["center"][1]) / height_px
        np.maximum(score, gaussian, out=score)
    return targets


def _terms_behind(prediction, targets):
    terms = _TERMS(prediction[:, :BEHIND], targets[:, :BEHIND])
    if prediction.shape[1] == BEHIND_CHANNELS:
        weight = targets[:, BEHIND]
        terms["detection"] = terms["detection"] + (prediction[:, BEHIND] - weight).square().mean()
        error = (prediction[:, BEHIND + 1:BEHIND + 3] - targets[:, BEHIND + 1:BEHIND + 3]).abs() * weight[:, None]
        if OFFSET_LOSS[0] == "weighted":  # the error in heights where the score's target is: a term of the others' size
            terms["centre_offsets"] = terms["centre_offsets"] + error.sum() / (2.0 * weight.sum()).clamp(min=1.0)
        else:  # "mean" over every cell, as the centre offsets' term: next to nothing under the few scores' Gaussians
            terms["centre_offsets"] = terms["centre_offsets"] + error.mean()
    return terms


# ---- decoding: the people behind added to the peaks

_CURRENT = threading.local()  # the runtime decodes its regions on several threads


def _heights_cells_at(xy_cells: np.ndarray, expected: np.ndarray, stride: int) -> np.ndarray:
    rows = np.clip(np.round(xy_cells[:, 1]).astype(int), 0, expected.shape[0] - 1)
    columns = np.clip(np.round(xy_cells[:, 0]).astype(int), 0, expected.shape[1] - 1)
    return expected[rows, columns].astype(float) / stride


def _find_peaks_behind(heatmap, threshold, limit=None):
    """The centre map's peaks, then the people behind the strong ones (when a decode of the behind layout asks)."""
    peaks = _FIND_PEAKS(heatmap, threshold, limit)
    current = getattr(_CURRENT, "pending", None)
    _CURRENT.pending, _CURRENT.behind = None, 0
    if current is None or not peaks:
        return peaks
    maps, config, expected, minimum = current
    stride = config.stride
    centres = np.array([centre for _, centre in peaks], float).reshape(-1, 2)
    kept = _SEPARATED(centres, _heights_cells_at(centres, expected, stride), config.min_centre_separation)
    kept_centres = centres[kept]
    added = []
    for index in kept:
        score, centre = peaks[index]
        if score < config.centre_threshold:
            continue
        column, row = np.clip(np.round(centre).astype(int), 0, [maps.shape[2] - 1, maps.shape[1] - 1])
        strength = float(maps[BEHIND, row, column])
        if strength < minimum:
            continue
        height = _heights_cells_at(centre[None], expected, stride)[0]
        point = centre + maps[BEHIND + 1:BEHIND + 3, row, column] * height
        reach = SAME_PERSON[0] * _heights_cells_at(point[None], expected, stride)[0]
        others = [c for c in kept_centres if not np.array_equal(c, centre)] + [p for _, p in added]
        if any(np.hypot(*(point - other)) < reach for other in others):
            continue
        added.append((min(strength, score), point))
    _CURRENT.behind = len(added)
    return peaks + added


def _separated_behind(centres_cells, heights_cells, separation):
    added = getattr(_CURRENT, "behind", 0)
    _CURRENT.behind = 0
    if not added:
        return _SEPARATED(centres_cells, heights_cells, separation)
    count = len(centres_cells) - added
    return _SEPARATED(centres_cells[:count], heights_cells[:count], separation) + list(range(count, count + added))


def decode_behind(heatmaps, config, expected_height_px=None, weak_above=None, prior=decoding.UPRIGHT_PRIOR):
    """:func:`vc.deploy.decode.decode`, the people behind added when the maps have the behind layout and
    :data:`THRESHOLD` is set; with :data:`FRONT_KEPT`, the others exactly as decoded without them (the people behind
    take no keypoint peak or mask cell from them)."""
    if heatmaps.shape[0] != BEHIND_CHANNELS or THRESHOLD[0] is None:
        return _DECODE(heatmaps, config, expected_height_px, weak_above, prior)
    front = _DECODE(heatmaps, config, expected_height_px, weak_above, prior) if FRONT_KEPT[0] else None
    _CURRENT.pending = (heatmaps, config, expected_height_px, THRESHOLD[0])
    try:
        people = _DECODE(heatmaps, config, expected_height_px, weak_above, prior)
    finally:
        _CURRENT.pending, _CURRENT.behind = None, 0
    if front is None:
        return people
    centres = {tuple(person.centre) for person in front}
    return front + [person for person in people if tuple(person.centre) not in centres]


_CHANNELS = codec.CodecConfig.channels
_SHIFTED = data_module.shifted
_ENCODE = codec.encode
_TERMS = loss_module.heatmap_terms
_FIND_PEAKS = decoding.find_peaks
_SEPARATED = decoding._separated
_DECODE = decoding.decode
THRESHOLD: list[float | None] = [None]
#: Whether the people decoded without the behind maps stay as they were (the added ones take nothing from them).
FRONT_KEPT = [False]
#: How the offsets' L1 is averaged: "weighted" (by the score's target) or "mean" (over every cell; behind0's).
OFFSET_LOSS = ["weighted"]


def install() -> None:
    """The behind layout made known to training and decoding."""
    layouts = (*decoding.LAYOUTS, BEHIND_CHANNELS)
    decoding.LAYOUTS = config_module.LAYOUTS = layouts
    codec.CodecConfig.channels = property(_channels)
    data_module.shifted = _shifted_keeping
    data_module.encode = _encode_behind
    loss_module.heatmap_terms = _terms_behind
    decoding.find_peaks = _find_peaks_behind
    decoding._separated = _separated_behind
    held_out.decode = decode_behind


def pairs(run: Path, renders: Path, region: str) -> None:
    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    config = checkpoint.config
    data = open_region(renders, region, config.held_out_fraction)
    net = ScenePoseNet(config.network)
    net.load_state_dict(checkpoint.content["model"])
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.codec.stride,
                                  checkpoint.content["reference_height_m"])
    evaluation = held_out.evaluate_network(net, data.held_out, config.decode, heights, torch.device("cpu"))
    overlapping = behind_someone = missed = missed_behind = 0
    for sample, matches in zip(data.held_out, evaluation.evaluation.matches, strict=True):
        _, instances = read_sample(sample)
        size = (instances.shape[1], instances.shape[0])
        behind = behind_of(sample.annotations, instances)
        behind_ids = {b for b in behind if b is not None}
        truth = np.array([_xyxy(a["amodal_bbox"]) for a in sample.annotations]).reshape(-1, 4)
        in_group = grouped(truth)
        matched = {t for t, _ in matches}
        for index, annotation in enumerate(sample.annotations):
            if not (in_group[index] and asked_for(annotation, size)):
                continue
            overlapping += 1
            behind_someone += index in behind_ids
            if index not in matched:
                missed += 1
                missed_behind += index in behind_ids
    print(f"{region}: {overlapping} held-out people overlapping another, {behind_someone} behind someone by the "
          f"rule; today's network misses {missed}, {missed_behind} of them behind someone")


def train(run: Path, renders: Path, region: str, out: Path, offset_loss: str, seen_below: float) -> None:
    checkpoint = load_checkpoint(run / "checkpoints" / f"{region}.pt")
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    paired = 0
    for sample in data.train:  # before the loader's workers fork
        _, instances = read_sample(sample)
        for annotation, behind in zip(sample.annotations, behind_of(sample.annotations, instances, seen_below),
                                      strict=True):
            annotation["behind_center"] = None if behind is None else sample.annotations[behind]["center"]
            paired += behind is not None
    print(f"{paired} people with someone behind them in {len(data.train)} training renders", flush=True)
    install()
    OFFSET_LOSS[0] = offset_loss
    config = dataclasses.replace(checkpoint.config)  # re-validated: the network now emits the behind layout
    trainer = RegionTrainer(data, config, out, renders, device=torch.device("cpu"), workers=1)
    trainer.train()


def measure(run: Path, renders: Path, region: str, weights: Path | None, thresholds: list[float | None]) -> None:
    install()
    checkpoint = load_checkpoint(weights or run / "checkpoints" / f"{region}.pt")
    config = checkpoint.config
    net = ScenePoseNet(config.network)
    net.load_state_dict(checkpoint.content["model"])
    data = open_region(renders, region, config.held_out_fraction)
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.codec.stride,
                                  load_checkpoint(run / "checkpoints" / f"{region}.pt").content["reference_height_m"])
    for threshold in thresholds:
        THRESHOLD[0] = threshold
        summary = held_out.evaluate_network(net, data.held_out, config.decode, heights, torch.device("cpu"),
                                            show_progress=False).evaluation.to_dict()
        print(f"{region} {weights or 'shipped'} behind threshold {threshold}, same person {SAME_PERSON[0]}"
              f"{', front kept' if FRONT_KEPT[0] else ''}: "
              f"AP50 {summary['ap50']:.4f}, people "
              f"overlapping another found {summary['recall_overlapping']:.4f} of {summary['overlapping']}, "
              f"detections {summary['detections']} (matched {summary['matched']} of {summary['ground_truth']}), "
              f"PCKh {summary['pckh']:.4f}", flush=True)


def _iou_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    top_left = np.maximum(a[:, None, :2], b[None, :, :2])
    bottom_right = np.minimum(a[:, None, 2:], b[None, :, 2:])
    inter = np.clip(bottom_right - top_left, 0, None).prod(axis=2)
    area = lambda boxes: (boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])  # noqa: E731
    return inter / (area(a)[:, None] + area(b)[None] - inter)


def added(run: Path, renders: Path, region: str, weights: Path, threshold: float) -> None:
    install()
    THRESHOLD[0] = threshold
    checkpoint = load_checkpoint(weights)
    config: DecodeConfig = checkpoint.config.decode
    net = ScenePoseNet(checkpoint.config.network)
    net.load_state_dict(checkpoint.content["model"])
    net.eval()
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.stride,
                                  load_checkpoint(run / "checkpoints" / f"{region}.pt")
                                  .content["reference_height_m"])
    kinds: Counter = Counter()
    results, added_flags, reaches, behind_lists, fronts = [], [], [], [], []
    fronts_behind: Counter = Counter()
    distances: dict[str, list[float]] = {}
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        base = _DECODE(maps[:FINE_CHANNELS], config, heights)
        people = decode_behind(maps, config, heights)
        base_centres = [tuple(np.round(person.centre, 3)) for person in base]
        added_flags.append([tuple(np.round(person.centre, 3)) not in base_centres for person in people])
        base_xy = np.array([person.centre for person in base]).reshape(-1, 2)
        behind_lists.append(behind_of(sample.annotations, instances))
        fronts.append([int(np.argmin(np.hypot(*(base_xy - person.centre).T))) if len(base_xy) else -1
                       for person in people])
        reaches.append([float(np.hypot(*(base_xy - person.centre).T).min(initial=np.inf)
                              / (person.box[3] - person.box[1])) for person in people])
        results.append(image_result(sample.annotations, instances, people, config.stride))
    evaluation = evaluate(results)
    for result, flags, reach, behind, front_of, matches in zip(results, added_flags, reaches, behind_lists, fronts,
                                                               evaluation.matches, strict=True):
        matched_truth = {truth: detection for truth, detection in matches}
        matched_detections = set(matched_truth.values())
        ious = _iou_matrix(np.asarray(result.boxes).reshape(-1, 4), np.asarray(result.truth_boxes).reshape(-1, 4))
        for index, added in enumerate(flags):
            if not added:
                continue
            if index in matched_detections:
                kinds["matched"] += 1
                distances.setdefault("matched", []).append(reach[index])
                continue
            best = int(np.argmax(ious[index])) if ious.shape[1] else -1
            best_iou = float(ious[index, best]) if best >= 0 else 0.0
            if best_iou >= 0.5 and result.truth_ignore[best]:
                kinds["on an ignored person"] += 1
            elif best_iou >= 0.5:
                kind = "a second box for a found person" if best in matched_truth else "on a person, not matched"
                kinds[kind] += 1
                if kind == "a second box for a found person":
                    front_truth = next((t for t, d in matches if d == front_of[index]), None)
                    behind_truth = None if front_truth is None else behind[front_truth]
                    fronts_behind["its front not matched" if front_truth is None else
                                  "no one behind its front" if behind_truth is None else
                                  "the one behind its front found" if behind_truth in matched_truth else
                                  "the one behind its front not found"] += 1
                distances.setdefault(kind, []).append(reach[index])
            elif best_iou >= 0.3:
                kinds["beside someone (IoU 0.3-0.5)"] += 1
            else:
                kinds["on no one"] += 1
    print(f"{region} threshold {threshold}: {sum(kinds.values())} added; " + ", ".join(
        f"{kind} {count}" for kind, count in kinds.most_common()))
    print("  second boxes: " + ", ".join(f"{kind} {count}" for kind, count in fronts_behind.most_common()))
    for kind, values in distances.items():
        print(f"  {kind}: nearest peak decoded without them at quartiles "
              + " / ".join(f"{q:.3f}" for q in np.quantile(values, [0.25, 0.5, 0.75])) + " of their box height")



def score(renders: Path, region: str, weights: Path) -> None:
    """How well the score map, read at each held-out person's centre, tells who has someone behind them (by the
    rule): the area under its ROC curve and the share read at T = 0.3 / 0.5 of each kind."""
    install()
    checkpoint = load_checkpoint(weights)
    net = ScenePoseNet(checkpoint.config.network)
    net.load_state_dict(checkpoint.content["model"])
    net.eval()
    stride = checkpoint.config.codec.stride
    data = open_region(renders, region, checkpoint.config.held_out_fraction)
    readings: dict[bool, list[float]] = {True: [], False: []}
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        for annotation, behind in zip(sample.annotations, behind_of(sample.annotations, instances), strict=True):
            if not asked_for(annotation, (instances.shape[1], instances.shape[0])):
                continue
            column, row = np.clip(np.round(input_to_cells([annotation["center"]], stride)[0]).astype(int), 0,
                                  [maps.shape[2] - 1, maps.shape[1] - 1])
            readings[behind is not None].append(float(maps[BEHIND, row, column]))
    positive, negative = np.array(readings[True]), np.array(readings[False])
    ranks = np.argsort(np.argsort(np.concatenate([positive, negative]))) + 1.0
    auc = (ranks[:len(positive)].sum() - len(positive) * (len(positive) + 1) / 2) / (len(positive) * len(negative))
    print(f"{region} {weights}: {len(positive)} people with someone behind, {len(negative)} without; "
          f"ROC AUC {auc:.3f}; read >= 0.3: {np.mean(positive >= 0.3):.3f} / {np.mean(negative >= 0.3):.3f}, "
          f">= 0.5: {np.mean(positive >= 0.5):.3f} / {np.mean(negative >= 0.5):.3f} (with / without)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("pairs", "train", "measure", "added", "score"))
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    parser.add_argument("-o", "--out", type=Path)
    parser.add_argument("--checkpoint", type=Path, help="measure, added: weights to read instead of RUN's")
    parser.add_argument("--threshold", type=float, nargs="*", default=[0.2, 0.3, 0.4, 0.5],
                        help="measure: the behind score that adds a person")
    parser.add_argument("--without", action="store_true", help="measure: also decoded without the people behind")
    parser.add_argument("--offset-loss", choices=("weighted", "mean"), default="weighted",
                        help="train: the offsets' L1 averaged under the score's target or over every cell")
    parser.add_argument("--seen-below", type=float, default=np.inf,
                        help="train: only people less seen than this (visible pixels over 0.45 of their full box) "
                             "count as behind")
    parser.add_argument("--front-kept", action="store_true",
                        help="measure: the people decoded without the behind maps stay exactly as they were")
    parser.add_argument("--same-person", type=float, default=SAME_PERSON[0],
                        help="measure: an added person this close to a peak (their heights) is that peak's")
    args = parser.parse_args()
    SAME_PERSON[0] = args.same_person
    FRONT_KEPT[0] = args.front_kept
    if args.what == "pairs":
        pairs(args.run, args.renders, args.region)
    elif args.what == "score":
        score(args.renders, args.region, args.checkpoint)
    elif args.what == "added":
        added(args.run, args.renders, args.region, args.checkpoint, args.threshold[0])
    elif args.what == "train":
        train(args.run, args.renders, args.region, args.out, args.offset_loss, args.seen_below)
    else:
        measure(args.run, args.renders, args.region, args.checkpoint,
                ([None] if args.without else []) + args.threshold)


if __name__ == "__main__":
    main()
