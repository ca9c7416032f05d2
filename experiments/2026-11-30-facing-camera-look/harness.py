"""Facing model variants, each trained on one compile's renders and read on the real people of the choosing half
(frozen, issue 57 item 4; decision record 0028).

    H=experiments/2026-11-30-facing-camera-look/harness.py
    PYTHONPATH=. python $H real CAMERA DETECTIONS_JSONL YOLO_CACHE OUT [BUNDLE]
    PYTHONPATH=. python $H renders RENDERS JITTER OUT
    PYTHONPATH=. python $H train VARIANT RENDER_NPZ REAL_NPZ[,REAL_NPZ] SEED
    PYTHONPATH=. python $H evaluate WEIGHTS REAL_NPZ[,REAL_NPZ]

* ``real``: the people a control bundle reports (score >= 0.5) on the choosing half, matched (IoU >= 0.5) to a
  YOLO11n-pose @1280 person whose shoulders and hips it reads clearly (the pose reference's own facing); their crops
  cut by the bundle's crop graph from the full frame, as the runtime cuts them.
* ``renders``: every whole rendered person facing the camera or away, cropped by the same graph from their amodal
  box, or JITTER times each from boxes moved and scaled as the detector's boxes differ from the labels.
* ``train``: one variant trained with the compile's seed; its accuracy on the held-out renders and on the real sets
  (all, by height) printed as one JSON line, its weights saved beside RENDER_NPZ.
* ``evaluate``: saved weights read on real sets (one made with BUNDLE, say: crops at the renders' scale).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import onnxruntime as ort
import torch
from torch import nn

from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.deploy.frames import FrameRange, FrameSource
from vc.io import read_image
from vc.model import facing as shipped
from vc.render.dataset import open_region, read_manifest

CHOOSING = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", FrameRange(1, 200, 5)),
            "tud": ("../shared/data/tud_stadtmitte/frames", FrameRange(1, 90, 1))}


def _iou(a, b) -> float:
    width, height = min(a[2], b[2]) - max(a[0], b[0]), min(a[3], b[3]) - max(a[1], b[1])
    if width <= 0 or height <= 0:
        return 0.0
    inter = width * height
    return inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter)


def yolo_facing(keypoints) -> int:
    """+1 seen from the front, -1 from behind, 0 unclear: YOLO's shoulders and hips, as 0027 measured them."""
    points = np.asarray(keypoints).reshape(17, 3)
    if points[[5, 6, 11, 12], 2].min() < 0.5:
        return 0
    share = sum(points[left, 0] - points[right, 0] for left, right in ((5, 6), (11, 12))) / max(np.ptp(points[:, 1]),
                                                                                              1.0)
    return 1 if share > 0.06 else (-1 if share < -0.06 else 0)


def real_set(camera: str, detections: Path, yolo_cache: Path, out: Path, bundle: Path | None = None) -> None:
    """With ``bundle``, each person is cut from the frame resized (area-averaged) to their region's network input
    scale, the scale the renders were made at; without, from the full frame, as the runtime cuts them."""
    video, frames = CHOOSING[camera]
    scales = {} if bundle is None else {
        entry["name"]: (entry["input_size"][0] / entry["crop_window"][2],
                        entry["input_size"][1] / entry["crop_window"][3])
        for entry in json.loads((bundle / "manifest.json").read_text())["regions"]}
    ours = {json.loads(line)["frame"]: json.loads(line)["people"] for line in detections.open()}
    yolo = json.loads(yolo_cache.read_text())
    session = ort.InferenceSession(shipped.crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    crops, front, heights = [], [], []
    for frame in FrameSource(Path(video), frames):
        for person in ours.get(frame.number, []):
            if person["score"] < 0.5:
                continue
            best = max(yolo.get(str(frame.number), []), key=lambda row: _iou(person["box"], row[0]), default=None)
            if best is None or _iou(person["box"], best[0]) < 0.5 or not yolo_facing(best[2]):
                continue
            if scales:
                sx, sy = scales[person["region"]]
                image = cv2.resize(frame.image, None, fx=sx, fy=sy, interpolation=cv2.INTER_AREA)
                box = np.array(person["box"]) * [sx, sy, sx, sy]
            else:
                image, box = frame.image, np.array(person["box"])
            cut = session.run(None, {FRAME_INPUT: image[None], ROIS_INPUT: crop_rois(box[None])})[0]
            crops.append(np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255), 0, 255).astype(np.uint8))
            front.append(yolo_facing(best[2]) > 0)
            heights.append(person["box"][3] - person["box"][1])
    np.savez_compressed(out, crops=np.concatenate(crops), front=np.array(front), heights=np.array(heights))
    print(out, len(front), "people, front share", np.mean(front))


def _jittered(boxes: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Boxes as a detector draws them: the height off by about 8 %, the centre by about 5 % of the height."""
    height = boxes[:, 3] - boxes[:, 1]
    width = boxes[:, 2] - boxes[:, 0]
    scale = np.exp(rng.normal(0, 0.08, len(boxes)))
    cx = (boxes[:, 0] + boxes[:, 2]) / 2 + rng.normal(0, 0.05, len(boxes)) * height
    cy = (boxes[:, 1] + boxes[:, 3]) / 2 + rng.normal(0, 0.04, len(boxes)) * height
    return np.stack([cx - width * scale / 2, cy - height * scale / 2, cx + width * scale / 2, cy + height * scale / 2],
                    axis=1)


def render_set(renders: Path, jitter: int, out: Path) -> None:
    session = ort.InferenceSession(shipped.crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    rng = np.random.default_rng(0)
    parts = {"train": ([], []), "held_out": ([], [])}
    for region in read_manifest(renders).get("regions", {}):
        data = open_region(renders, region)
        for split, samples in (("train", data.train), ("held_out", data.held_out)):
            for sample in samples:
                boxes, facing = [], []
                for annotation in sample.annotations:
                    x, y, width, height = annotation["amodal_bbox"]
                    if height < shipped.MIN_HEIGHT_PX or annotation["bbox"][3] < shipped.MIN_VISIBLE_SHARE * height:
                        continue
                    seen = shipped.seen_from_front(annotation)
                    if seen is not None:
                        boxes.append([x, y, x + width, y + height])
                        facing.append(seen)
                if not boxes:
                    continue
                boxes = np.array(boxes)
                copies = ([boxes] if not jitter or split == "held_out"
                          else [_jittered(boxes, rng) for _ in range(jitter)])
                image = read_image(sample.image_path)
                for copy in copies:
                    cut = session.run(None, {FRAME_INPUT: image[None], ROIS_INPUT: crop_rois(copy)})[0]
                    parts[split][0].append(np.clip(np.rint(cut.transpose(0, 2, 3, 1) * 255), 0, 255).astype(np.uint8))
                    parts[split][1].extend(facing)
    np.savez_compressed(out, **{f"{split}_crops": np.concatenate(crops) for split, (crops, _) in parts.items()},
                        **{f"{split}_front": np.array(front) for split, (_, front) in parts.items()})
    print(out, {split: len(front) for split, (_, front) in parts.items()})


def _fewer_pixels(crop: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The person seen with fewer pixels than the render had: down by up to 2.5x and back up."""
    factor = rng.uniform(0.4, 1.0)
    height, width = crop.shape[:2]
    small = cv2.resize(crop, (max(4, round(width * factor)), max(8, round(height * factor))),
                       interpolation=cv2.INTER_AREA)
    return cv2.resize(small, (width, height), interpolation=cv2.INTER_LINEAR)


VARIANTS = {
    # name: (widths, epochs, fewer-pixels probability, mirror average at reading)
    "shipped": ((8, 16, 32), 8, 0.0, False),
    "tta": ((8, 16, 32), 8, 0.0, True),
    "pixels": ((8, 16, 32), 8, 0.5, False),
    "wide": ((16, 32, 64), 8, 0.0, False),
    "long": ((8, 16, 32), 16, 0.0, False),
    "pixels_wide": ((16, 32, 64), 8, 0.5, False),
}


def _logits(net: nn.Module, crops: np.ndarray, mirror_average: bool) -> np.ndarray:
    net.eval()
    with torch.no_grad():
        out = []
        for start in range(0, len(crops), 512):
            batch = shipped._batch(crops[start:start + 512])
            logit = net(batch)
            if mirror_average:
                logit = (logit + net(batch.flip(3))) / 2
            out.append(logit)
    return torch.cat(out).numpy()


def train(variant: str, renders_npz: Path, real_npzs: list[Path], seed: int) -> None:
    widths, epochs, fewer, mirror_average = VARIANTS[variant]
    data = np.load(renders_npz)
    train_crops, train_front = data["train_crops"], data["train_front"]
    start = time.perf_counter()
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = shipped.FacingNet(widths)
    steps_per_epoch = len(train_front) // shipped.BATCH
    optimiser = torch.optim.AdamW(net.parameters(), shipped.LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, shipped.LEARNING_RATE,
                                                   total_steps=epochs * steps_per_epoch)
    loss_of = nn.BCEWithLogitsLoss()
    labels = torch.from_numpy(train_front.astype(np.float32))
    for _ in range(epochs):
        net.train()
        order = rng.permutation(len(train_front))
        for step in range(steps_per_epoch):
            chosen = order[step * shipped.BATCH:(step + 1) * shipped.BATCH]
            looks = []
            for crop in train_crops[chosen]:
                if fewer and rng.random() < fewer:
                    crop = _fewer_pixels(crop, rng)
                looks.append(shipped.camera_look(crop, rng))
            looks = np.stack(looks)
            mirrored = rng.random(len(chosen)) < 0.5
            looks[mirrored] = looks[mirrored, :, ::-1]
            loss = loss_of(net(shipped._batch(looks)), labels[chosen])
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
    row = {"variant": variant, "renders": renders_npz.stem, "seed": seed, "seconds": round(time.perf_counter() - start),
           "weights": sum(p.numel() for p in net.parameters())}
    torch.save(net.state_dict(), renders_npz.with_name(f"{variant}_{renders_npz.stem}_{seed}.pt"))
    held = _logits(net, data["held_out_crops"], mirror_average)
    row["renders_held_out"] = round(float(((held > 0) == data["held_out_front"]).mean()), 4)
    print(json.dumps({**row, **read_real(net, real_npzs, mirror_average)}), flush=True)


def read_real(net: nn.Module, real_npzs: list[Path], mirror_average: bool) -> dict:
    """The share of each real set's people ``net`` reads as YOLO does, overall and by height."""
    row = {}
    for path in real_npzs:
        real = np.load(path)
        logits = _logits(net, real["crops"], mirror_average)
        right = (logits > 0) == real["front"]
        row[path.stem] = round(float(right.mean()), 4)
        row[f"{path.stem}_auc"] = round(_auc(real["front"], logits), 4)
        row[f"{path.stem}_front_right"] = round(float(right[real["front"]].mean()), 4)
        row[f"{path.stem}_behind_right"] = round(float(right[~real["front"]].mean()), 4)
        for low, high in ((0, 60), (60, 100), (100, 1000)):
            inside = (real["heights"] >= low) & (real["heights"] < high)
            if inside.any():
                row[f"{path.stem}_{low}-{high}px"] = [round(float(right[inside].mean()), 3), int(inside.sum())]
    return row


def _auc(front: np.ndarray, logits: np.ndarray) -> float:
    """The chance that a person seen from the front gets a higher logit than one seen from behind (ranks; no ties
    among float logits)."""
    ranks = np.empty(len(logits))
    ranks[np.argsort(logits)] = np.arange(1, len(logits) + 1)
    fronts = int(front.sum())
    return float((ranks[front].sum() - fronts * (fronts + 1) / 2) / (fronts * (len(front) - fronts)))


def evaluate(weights: Path, real_npzs: list[Path]) -> None:
    variant = weights.stem.split("_")[0] if not weights.stem.startswith("pixels_wide") else "pixels_wide"
    widths, _, _, mirror_average = VARIANTS[variant]
    net = shipped.FacingNet(widths)
    net.load_state_dict(torch.load(weights))
    print(json.dumps({"weights": weights.stem, **read_real(net, real_npzs, mirror_average)}), flush=True)


if __name__ == "__main__":
    torch.set_num_threads(1)
    command = sys.argv[1]
    if command == "real":
        real_set(sys.argv[2], Path(sys.argv[3]), Path(sys.argv[4]), Path(sys.argv[5]),
                 Path(sys.argv[6]) if len(sys.argv) > 6 else None)
    elif command == "renders":
        render_set(Path(sys.argv[2]), int(sys.argv[3]), Path(sys.argv[4]))
    elif command == "evaluate":
        evaluate(Path(sys.argv[2]), [Path(path) for path in sys.argv[3].split(",")])
    else:
        train(sys.argv[2], Path(sys.argv[3]), [Path(path) for path in sys.argv[4].split(",")], int(sys.argv[5]))
