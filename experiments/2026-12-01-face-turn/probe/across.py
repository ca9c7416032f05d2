"""Can the facing classifier, trained on renders, tell a face pointing to the image's left from one pointing right
on real people? (frozen probe of decision 0038)

    PYTHONPATH=.:experiments/2026-11-30-facing-camera-look python experiments/2026-12-01-face-turn/probe/across.py \
        real CAMERA DETECTIONS_JSONL YOLO_CACHE OUT.npz
    ... across.py train RENDERS_NPZ REAL_NPZ[,REAL_NPZ] SEED

``real``: the bundle's people of a choosing half (score >= 0.5, from a vc-eval detections.jsonl) matched to a
YOLO11n-pose @1280 person (IoU >= 0.5) whose nose and an ear it reads (confidence >= 0.5), the nose at least 0.03 of
the box height from the ears' midpoint; cut from the bundle's own boxes. ``train``: the shipped facing classifier's
recipe on detector_crops.py's crops, a mirror turning the label round; accuracy and AUC on each real set.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import onnxruntime as ort
import torch
from harness import CHOOSING, _auc, _iou
from torch import nn

from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.deploy.frames import FrameSource
from vc.model import facing as shipped


def real_set(camera: str, detections: str, cache: str, out: str) -> None:
    video, frames = CHOOSING[camera]
    ours = {json.loads(line)["frame"]: json.loads(line)["people"] for line in open(detections)}
    yolo = json.loads(Path(cache).read_text())
    cut = ort.InferenceSession(shipped.crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    crops, labels = [], []
    for frame in FrameSource(Path(video), frames):
        boxes = []
        for person in ours.get(frame.number, []):
            if person["score"] < 0.5:
                continue
            best = max(yolo.get(str(frame.number), []), key=lambda row: _iou(person["box"], row[0]), default=None)
            if best is None or _iou(person["box"], best[0]) < 0.5:
                continue
            points = np.reshape(best[2], (17, 3))
            if points[0, 2] < 0.5 or points[3:5, 2].max() < 0.5:
                continue
            ears = points[3:5][points[3:5, 2] >= 0.5, 0].mean()
            offset = (points[0, 0] - ears) / (person["box"][3] - person["box"][1])
            if abs(offset) < 0.03:
                continue
            boxes.append(person["box"])
            labels.append(offset > 0)
        if boxes:
            found = cut.run(None, {FRAME_INPUT: frame.image[None], ROIS_INPUT: crop_rois(np.array(boxes))})[0]
            crops.append(np.clip(np.rint(found.transpose(0, 2, 3, 1) * 255), 0, 255).astype(np.uint8))
    np.savez_compressed(out, crops=np.concatenate(crops), right=np.array(labels))
    print(out, len(labels), "right share", np.mean(labels))


def logits(net: nn.Module, crops: np.ndarray) -> np.ndarray:
    net.eval()
    with torch.no_grad():
        return torch.cat([net(shipped._batch(crops[i:i + 512])) for i in range(0, len(crops), 512)]).numpy()


def train(renders_npz: str, real_npzs: list[str], seed: int) -> None:
    data = np.load(renders_npz)
    crops, right = data["train_crops"], data["train_front"]
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    net = shipped.FacingNet()
    steps = len(right) // shipped.BATCH
    optimiser = torch.optim.AdamW(net.parameters(), shipped.LEARNING_RATE / 1.5, weight_decay=1e-4)
    schedule = torch.optim.lr_scheduler.OneCycleLR(optimiser, shipped.LEARNING_RATE,
                                                   total_steps=shipped.EPOCHS * steps)
    loss_of = nn.BCEWithLogitsLoss()
    for _ in range(shipped.EPOCHS):
        net.train()
        order = rng.permutation(len(right))
        for step in range(steps):
            chosen = order[step * shipped.BATCH:(step + 1) * shipped.BATCH]
            looks = np.stack([shipped.camera_look(crop, rng) for crop in crops[chosen]])
            label = right[chosen].astype(np.float32).copy()
            mirrored = rng.random(len(chosen)) < 0.5
            looks[mirrored] = looks[mirrored, :, ::-1]
            label[mirrored] = 1 - label[mirrored]  # a mirror turns the face the other way
            loss = loss_of(net(shipped._batch(looks)), torch.from_numpy(label))
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
    held = logits(net, data["held_out_crops"])
    row = {"seed": seed, "held_out": round(float(((held > 0) == data["held_out_front"]).mean()), 3)}
    for path in real_npzs:
        real = np.load(path)
        read = logits(net, real["crops"])
        accuracy = round(float(((read > 0) == real["right"]).mean()), 3)
        row[Path(path).stem] = [accuracy, round(_auc(real["right"], read), 3), len(read)]
    print(json.dumps(row))


if __name__ == "__main__":
    if sys.argv[1] == "real":
        real_set(*sys.argv[2:6])
    else:
        train(sys.argv[2], sys.argv[3].split(","), int(sys.argv[4]))
