"""The person behind, read from the crop of the person in front (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python behind_crop.py crops RENDERS -o CROPS.npz [--seed S]
    PYTHONPATH=../../src python behind_crop.py train CROPS.npz -o NET.pt [--samples N] [--seed S]
    PYTHONPATH=../../src python behind_crop.py measure CROPS.npz NET.pt
    PYTHONPATH=../../src python behind_crop.py real BUNDLE NET.pt [--threshold T ...] [--duplicate IOU ...]

The people TUD-Stadtmitte's bundles miss in groups stand behind a found person, under one centre peak
(``../2026-12-03-second-look/``). Read from the region network's own peak, a score that someone stands behind tells
them from people with nobody behind at ROC AUC 0.79 only (``../2026-12-03-second-person/``), which no threshold
makes worth reporting. The issue names "a second look at crops where two centres compete". Here a small network
sees one found person's crop, as the keypoint model does (``vc.model.crop_pose``), and is taught to mark the centre
of each person standing behind them, with that person's box:

1. **Crops** (``crops``): every person P of a compile's renders the evaluation asks for (at least half their height
   seen), who would stand at least :data:`MIN_FRAME_HEIGHT` px tall in the frame, cut square (:data:`CROP_SIZE`,
   :data:`CROP_MARGIN` times P's height on each side) about a box jittered as a region network draws one
   (``crop_pose.BOX_JITTER``). Behind P (:func:`behind_all`): everyone else the evaluation asks for whose feet lie
   higher in the image, whose amodal box overlaps P's (IoU >= 0.1) and whose centre lies within
   :data:`BEHIND_REACH` of P's height of P's centre (``second_person.behind_of``'s rule, every such person).
2. **Network**: ``crop_pose.CropPoseNet`` with three maps: a Gaussian at each behind person's centre (the score),
   and under it the log of their amodal box's height and width over P's jittered box's.
3. **Training**: the score's squared error weighted toward its peaks (as the keypoint model's), the two logs' L1
   under the Gaussians' cores; each crop in the camera's look and mirrored half the time; seeded.
4. **Reading** (``real``): the bundle's people, as the runtime reports them each frame; each person at least
   ``crop_pose.MIN_READ_HEIGHT_PX`` tall is cut and read; each local maximum of the score at or above T adds a
   person there with the read box, scored min(peak, P's score), unless its box overlaps a person already reported
   or added at IoU >= the duplicate threshold.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import onnxruntime as ort
import torch
from torch import Tensor, nn
from tqdm import tqdm

from vc.deploy.crop_pose import MIN_READ_HEIGHT_PX
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import ImageResult, box_iou, evaluate, grouped
from vc.evaluation.mot import read_mot_boxes
from vc.evaluation.renders import asked_for
from vc.io import read_image
from vc.model.crop_pose import BOX_JITTER, CropPoseNet
from vc.model.facing import camera_look, crop_graph
from vc.render.dataset import open_region, read_manifest

#: Square crops (width, height) and their half-side in P's heights: 0.55 keeps the crop as tall as the keypoint
#: model's (1.1 heights) and wide enough for a person standing up to half a body beside P.
CROP_SIZE = (96, 96)
CROP_MARGIN = 0.55
MAP_STRIDE = 2
#: The people who are read: as tall in the frame as the keypoint model's training crops (0.8 x 100 px).
MIN_FRAME_HEIGHT = 80.0
BEHIND_REACH = 0.5
OVERLAP_IOU = 0.1
#: The score Gaussian's sigma in map cells; its core (>= 0.5) carries the box's logs.
SIGMA_CELLS = 1.5
CORE = 0.5
PEAK_WEIGHT = 10.0
LOSS_SCALE = 100.0
BATCH = 64
LEARNING_RATE = 2e-3
SAMPLES_SEEN = 200_000

VIDEO = Path("../shared/data/tud_stadtmitte/frames")
GROUND_TRUTH = Path("../shared/data/tud_stadtmitte/gt_world.txt")
HALVES = {"choosing": (1, 90), "confirming": (91, 179)}


def _xyxy(box: list[float]) -> np.ndarray:
    x, y, width, height = box
    return np.array([x, y, x + width, y + height], float)


def square_rois(boxes: np.ndarray) -> np.ndarray:
    """The crops' rectangles (N, 4, pixel edges) of ``boxes`` (N, 4, outer edges): square, 2 x CROP_MARGIN of the
    box's height a side, about the box's centre."""
    boxes = np.asarray(boxes, np.float64).reshape(-1, 4)
    half = (boxes[:, 3] - boxes[:, 1]) * CROP_MARGIN
    centre_x, centre_y = (boxes[:, 0] + boxes[:, 2]) / 2.0 + 0.5, (boxes[:, 1] + boxes[:, 3]) / 2.0 + 0.5
    return np.stack([centre_x - half, centre_y - half, centre_x + half, centre_y + half], 1).astype(np.float32)


def behind_all(annotations: list[dict], size: tuple[int, int]) -> list[list[int]]:
    """For each annotation, the people behind them (step 1's rule)."""
    asked = [i for i, a in enumerate(annotations) if asked_for(a, size)]
    result: list[list[int]] = [[] for _ in annotations]
    for front in asked:
        box = _xyxy(annotations[front]["amodal_bbox"])
        height = box[3] - box[1]
        centre = annotations[front]["center"]
        for other in asked:
            other_box = _xyxy(annotations[other]["amodal_bbox"])
            if other == front or other_box[3] >= box[3]:
                continue
            if box_iou(box[None], other_box[None])[0, 0] < OVERLAP_IOU:
                continue
            other_centre = annotations[other]["center"]
            if np.hypot(other_centre[0] - centre[0], other_centre[1] - centre[1]) > BEHIND_REACH * height:
                continue
            result[front].append(other)
    return result


def crops(renders: Path, out: Path, seed: int) -> None:
    """Step 1 for every region's training and held-out renders: crops, and per crop the people behind in crop
    pixels (centre x, y, log height ratio, log width ratio)."""
    rng = np.random.default_rng(seed)
    session = ort.InferenceSession(crop_graph(CROP_SIZE).SerializeToString(), providers=["CPUExecutionProvider"])
    arrays: dict[str, list] = {}
    for region, entry in read_manifest(renders).get("regions", {}).items():
        data = open_region(renders, region)
        min_height = MIN_FRAME_HEIGHT * entry["input_size"][1] / entry["crop_window"][3]
        for split, samples in (("train", data.train), ("held_out", data.held_out)):
            for sample in tqdm(samples, desc=f"{region} {split}", leave=False):
                image = read_image(sample.image_path)
                size = (image.shape[1], image.shape[0])
                behind = behind_all(sample.annotations, size)
                fronts = [i for i, a in enumerate(sample.annotations)
                          if asked_for(a, size) and a["amodal_bbox"][3] >= min_height]
                if not fronts:
                    continue
                boxes = []
                for index in fronts:
                    x, y, width, height = sample.annotations[index]["amodal_bbox"]
                    centre = np.array([x + width / 2, y + height / 2]) + rng.normal(0.0, BOX_JITTER, 2) * height
                    tall, wide = height * np.exp(rng.normal(0.0, BOX_JITTER, 2))
                    boxes.append([centre[0] - wide / 2, centre[1] - tall / 2, centre[0] + wide / 2,
                                  centre[1] + tall / 2])
                boxes = np.array(boxes)
                rois = square_rois(boxes)
                cut = session.run(None, {FRAME_INPUT: image[None], ROIS_INPUT: rois})[0]
                arrays.setdefault(f"{split}_crops", []).append(
                    np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255.0), 0, 255).astype(np.uint8))
                for index, box, roi in zip(fronts, boxes, rois, strict=True):
                    scale = (roi[2] - roi[0]) / CROP_SIZE[0]
                    people = []
                    for other in behind[index]:
                        other_box = _xyxy(sample.annotations[other]["amodal_bbox"])
                        cx, cy = sample.annotations[other]["center"]
                        people.append([(cx + 0.5 - roi[0]) / scale - 0.5, (cy + 0.5 - roi[1]) / scale - 0.5,
                                       np.log((other_box[3] - other_box[1]) / (box[3] - box[1])),
                                       np.log((other_box[2] - other_box[0]) / (box[2] - box[0]))])
                    targets = np.full((4, 4), np.nan, np.float32)  # at most four people behind one
                    targets[:min(len(people), 4)] = np.array(people, np.float32).reshape(-1, 4)[:4]
                    arrays.setdefault(f"{split}_behind", []).append(targets)
                    arrays.setdefault(f"{split}_front", []).append(
                        np.array([box[3] - box[1], box[2] - box[0]], np.float32) / scale)
    joined = {key: np.concatenate(value) if key.endswith("crops") else np.array(value)
              for key, value in arrays.items()}
    np.savez(out, **joined)
    for split in ("train", "held_out"):
        behind = joined[f"{split}_behind"]
        with_someone = int(np.isfinite(behind[:, 0, 0]).sum())
        print(f"{split}: {len(behind)} crops, {with_someone} with someone behind")


def behind_net() -> CropPoseNet:
    net = CropPoseNet()
    net.maps = nn.Conv2d(net.maps.in_channels, 3, 1)
    return net


def _targets(behind: np.ndarray) -> tuple[Tensor, Tensor]:
    """Score maps (N, 1, h, w) and log-ratio maps (N, 2, h, w) of ``behind`` (N, 4, 4) in crop pixels."""
    rows, columns = np.mgrid[0:CROP_SIZE[1] // MAP_STRIDE, 0:CROP_SIZE[0] // MAP_STRIDE].astype(np.float32)
    score = np.zeros((len(behind), 1, *rows.shape), np.float32)
    logs = np.zeros((len(behind), 2, *rows.shape), np.float32)
    for n, people in enumerate(behind):
        for person in people:
            if not np.isfinite(person[0]):
                continue
            cx, cy = (person[:2] + 0.5) / MAP_STRIDE - 0.5
            gaussian = np.exp(-((columns - cx) ** 2 + (rows - cy) ** 2) / (2 * SIGMA_CELLS**2))
            core = (gaussian >= CORE) & (gaussian >= score[n, 0])
            logs[n, 0][core], logs[n, 1][core] = person[2], person[3]
            np.maximum(score[n, 0], gaussian, out=score[n, 0])
    return torch.from_numpy(score), torch.from_numpy(logs)


def _mirrored(looks: np.ndarray, behind: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    flipped = behind.copy()
    flipped[..., 0] = CROP_SIZE[0] - 1 - flipped[..., 0]
    return looks[:, :, ::-1], flipped


def _batch(crops_: np.ndarray) -> Tensor:
    return torch.from_numpy(np.ascontiguousarray(crops_)).permute(0, 3, 1, 2).float() / 255.0


def train(data: Path, out: Path, samples: int, seed: int) -> None:
    """Step 3."""
    arrays = np.load(data)
    crops_, behind = arrays["train_crops"], arrays["train_behind"]
    start = time.perf_counter()
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = behind_net()
    steps = max(1, samples // BATCH)
    optimiser = torch.optim.AdamW(net.parameters(), LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, LEARNING_RATE, total_steps=steps)
    order = np.zeros(0, np.int64)
    net.train()
    for _ in tqdm(range(steps), desc="behind from the crop", unit="step", mininterval=30):
        if len(order) < BATCH:
            order = rng.permutation(len(crops_))
        chosen, order = order[:BATCH], order[BATCH:]
        looks = np.stack([camera_look(crop, rng) for crop in crops_[chosen]])
        targets = behind[chosen]
        flip = rng.random(len(chosen)) < 0.5
        looks[flip], targets[flip] = _mirrored(looks[flip], targets[flip])
        score, logs = _targets(targets)
        maps = net(_batch(looks))
        squared = ((maps[:, :1] - score) ** 2 * (1.0 + PEAK_WEIGHT * score)).mean()
        core = (score >= CORE).float()
        l1 = ((maps[:, 1:] - logs).abs() * core).sum() / (2.0 * core.sum()).clamp(min=1.0)
        loss = squared * LOSS_SCALE + l1
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        schedule.step()
    torch.save(net.state_dict(), out)
    print(f"trained on {len(crops_)} crops, {samples} seen, in {time.perf_counter() - start:.0f} s -> {out}")


def load(path: Path) -> CropPoseNet:
    net = behind_net()
    net.load_state_dict(torch.load(path))
    net.eval()
    return net


def read_maps(net: CropPoseNet, crops_: np.ndarray) -> np.ndarray:
    with torch.no_grad():
        return np.concatenate([net(_batch(crops_[start:start + 256])).numpy()
                               for start in range(0, len(crops_), 256)]) if len(crops_) else np.zeros(
            (0, 3, CROP_SIZE[1] // MAP_STRIDE, CROP_SIZE[0] // MAP_STRIDE), np.float32)


def peaks(maps: np.ndarray, threshold: float) -> list[list[tuple[float, float, float, float, float]]]:
    """Each crop's local maxima of the score at or above ``threshold``: (score, x, y in crop pixels, log height
    ratio, log width ratio)."""
    score = torch.from_numpy(maps[:, :1])
    local = (score == nn.functional.max_pool2d(score, 3, 1, 1)) & (score >= threshold)
    found = []
    for n in range(len(maps)):
        rows, columns = np.nonzero(local[n, 0].numpy())
        found.append([(float(maps[n, 0, r, c]), (c + 0.5) * MAP_STRIDE - 0.5, (r + 0.5) * MAP_STRIDE - 0.5,
                       float(maps[n, 1, r, c]), float(maps[n, 2, r, c])) for r, c in zip(rows, columns, strict=True)])
    return found


def measure(data: Path, weights: Path) -> None:
    """The held-out crops: how well the strongest score tells crops with someone behind (ROC AUC), and, per
    threshold, the share of people behind whose box a peak reads at IoU >= 0.5 and the peaks that read nobody."""
    arrays = np.load(data)
    crops_, behind, fronts = arrays["held_out_crops"], arrays["held_out_behind"], arrays["held_out_front"]
    maps = read_maps(load(weights), crops_)
    strongest = maps[:, 0].reshape(len(maps), -1).max(axis=1)
    has = np.isfinite(behind[:, 0, 0])
    positive, negative = strongest[has], strongest[~has]
    ranks = np.argsort(np.argsort(np.concatenate([positive, negative]))) + 1.0
    auc = (ranks[:len(positive)].sum() - len(positive) * (len(positive) + 1) / 2) / (len(positive) * len(negative))
    print(f"{len(crops_)} held-out crops, {has.sum()} with someone behind; strongest score's ROC AUC {auc:.3f}")
    for threshold in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7):
        found = people = wrong = count = 0
        for n, read in enumerate(peaks(maps, threshold)):
            truth = [p for p in behind[n] if np.isfinite(p[0])]
            boxes = np.array([_box_of(p, fronts[n]) for p in truth]).reshape(-1, 4)
            predicted = np.array([_box_of(np.array(p[1:]), fronts[n]) for p in read]).reshape(-1, 4)
            people += len(truth)
            count += len(read)
            if len(truth) and len(read):
                iou = box_iou(predicted, boxes)
                found += int((iou.max(axis=0) >= 0.5).sum())
                wrong += int((iou.max(axis=1) < 0.5).sum())
            else:
                wrong += len(read)
        print(f"  T {threshold}: people behind read at IoU >= 0.5 {found / max(people, 1):.3f} of {people}; "
              f"peaks {count}, reading nobody {wrong} ({wrong / max(count, 1):.3f})")


def _box_of(person: np.ndarray, front: np.ndarray) -> np.ndarray:
    """A behind person's box (outer edges, crop pixels) from their centre and log ratios to the front box (height,
    width in crop pixels)."""
    cx, cy, log_h, log_w = person[:4]
    height, width = front[0] * np.exp(log_h), front[1] * np.exp(log_w)
    return np.array([cx + 0.5 - width / 2, cy + 0.5 - height / 2, cx + 0.5 + width / 2, cy + 0.5 + height / 2])


def added_people(frame: np.ndarray, boxes: np.ndarray, scores: np.ndarray, net: CropPoseNet,
                 session: ort.InferenceSession, threshold: float, duplicate: float) -> tuple[np.ndarray, np.ndarray]:
    """Step 4: the people read behind the reported ones (boxes N x 4, scores N)."""
    tall = (boxes[:, 3] - boxes[:, 1]) >= MIN_READ_HEIGHT_PX
    if not tall.any():
        return np.zeros((0, 4)), np.zeros(0)
    rois = square_rois(boxes[tall])
    cut = session.run(None, {FRAME_INPUT: frame[None], ROIS_INPUT: rois})[0]
    maps = read_maps(net, np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255.0), 0, 255).astype(np.uint8))
    kept_boxes, kept_scores = list(boxes), []
    for box, score, roi, read in zip(boxes[tall], scores[tall], rois, peaks(maps, threshold), strict=True):
        scale = (roi[2] - roi[0]) / CROP_SIZE[0]
        for peak, x, y, log_h, log_w in sorted(read, reverse=True):
            cx, cy = roi[0] + (x + 0.5) * scale - 0.5, roi[1] + (y + 0.5) * scale - 0.5
            height = (box[3] - box[1]) * np.exp(log_h)
            width = (box[2] - box[0]) * np.exp(log_w)
            candidate = np.array([cx + 0.5 - width / 2, cy + 0.5 - height / 2, cx + 0.5 + width / 2,
                                  cy + 0.5 + height / 2])
            if box_iou(candidate[None], np.array(kept_boxes))[0].max() >= duplicate:
                continue
            kept_boxes.append(candidate)
            kept_scores.append(min(peak, float(score)))
    return np.array(kept_boxes[len(boxes):]).reshape(-1, 4), np.array(kept_scores)


def real(bundle: Path, weights: Path, thresholds: list[float], duplicates: list[float]) -> None:
    """TUD-Stadtmitte's halves each frame: AP50, everyone reported (precision, recall) and the recall of people
    overlapping another, the bundle alone and with the people behind added."""
    net = load(weights)
    session = ort.InferenceSession(crop_graph(CROP_SIZE).SerializeToString(), providers=["CPUExecutionProvider"])
    truth = read_mot_boxes(GROUND_TRUTH)
    runtime = Runtime(bundle, threads=2)
    try:
        for half, (first, last) in HALVES.items():
            frames = []
            for frame in FrameSource(VIDEO, FrameRange(first, last, 1)):
                people = [person for person in runtime.run(frame.image).people if not person.weak]
                frames.append((frame.number, frame.image, np.array([p.box for p in people]).reshape(-1, 4),
                               np.array([p.score for p in people])))
            arms = [("bundle", None, None)] + [(f"T {t}, duplicate IoU {d}", t, d)
                                               for t in thresholds for d in duplicates]
            for name, threshold, duplicate in arms:
                images = []
                for number, image, boxes, scores in frames:
                    if threshold is not None:
                        extra, extra_scores = added_people(image, boxes, scores, net, session, threshold, duplicate)
                        boxes, scores = np.concatenate([boxes, extra]), np.concatenate([scores, extra_scores])
                    images.append(ImageResult(truth_boxes=truth.get(number, np.zeros((0, 4))), boxes=boxes,
                                              scores=scores))
                _report(half, name, images)
    finally:
        runtime.close()


def _report(half: str, name: str, images: list[ImageResult]) -> None:
    evaluation = evaluate(images)
    detections = sum(len(image.scores) for image in images)
    matched = sum(len(pairs) for pairs in evaluation.matches)
    in_group = found_in_group = 0
    for image, matches in zip(images, evaluation.matches, strict=True):
        group = grouped(np.asarray(image.truth_boxes).reshape(-1, 4))
        in_group += int(group.sum())
        found_in_group += sum(int(group[t]) for t, _ in matches)
    precision, recall = matched / max(detections, 1), matched / evaluation.ground_truth
    f1 = 2 * precision * recall / (precision + recall)
    print(f"{half} {name}: AP50 {evaluation.ap50:.4f}; {detections} reported, {matched} of {evaluation.ground_truth} "
          f"found: precision {precision:.3f}, recall {recall:.3f}, F1 {f1:.3f};"
          f" overlapping another {found_in_group} of {in_group} ({found_in_group / max(in_group, 1):.3f})", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("crops", "train", "measure", "real"))
    parser.add_argument("paths", nargs="+", type=Path)
    parser.add_argument("-o", "--out", type=Path)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--samples", type=int, default=SAMPLES_SEEN)
    parser.add_argument("--threshold", type=float, nargs="*", default=[0.3, 0.5, 0.7])
    parser.add_argument("--duplicate", type=float, nargs="*", default=[0.5, 0.7])
    args = parser.parse_args()
    if args.what == "crops":
        crops(args.paths[0], args.out, args.seed)
    elif args.what == "train":
        train(args.paths[0], args.out, args.samples, args.seed)
    elif args.what == "measure":
        measure(*args.paths)
    else:
        real(args.paths[0], args.paths[1], args.threshold, args.duplicate)


if __name__ == "__main__":
    main()
