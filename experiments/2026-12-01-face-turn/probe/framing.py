"""How the shipped front-from-behind classifier reads people when their boxes are drawn a little larger, smaller or
higher: held-out renders (their exact amodal boxes scaled) and real people (the bundle's boxes scaled or shifted)
(frozen side measurement of decision 0038).

    PYTHONPATH=.:experiments/2026-11-30-facing-camera-look python experiments/2026-12-01-face-turn/probe/framing.py \
        renders BUNDLE RENDERS
    ... framing.py real BUNDLE CAMERA DETECTIONS_JSONL YOLO_CACHE
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from harness import CHOOSING, _auc, _iou, yolo_facing

from vc.deploy.facing import FacingReader
from vc.deploy.frames import FrameSource
from vc.io import read_image
from vc.model import facing as shipped
from vc.render.dataset import open_region, read_manifest

SCALES = (0.8, 0.9, 1.0, 1.1, 1.2, 1.35)
SHIFTS = (-0.08, -0.04, 0.04, 0.08)


def moved(boxes: np.ndarray, scale: float, shift: float) -> np.ndarray:
    """``boxes`` scaled about their centre and moved down by ``shift`` of their height."""
    centre_x, centre_y = (boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2
    height, width = boxes[:, 3] - boxes[:, 1], boxes[:, 2] - boxes[:, 0]
    centre_y = centre_y + shift * height
    return np.stack([centre_x - width * scale / 2, centre_y - height * scale / 2,
                     centre_x + width * scale / 2, centre_y + height * scale / 2], axis=1)


def report(name: str, variants: list[tuple[float, float]], logits: dict, front: np.ndarray) -> None:
    for variant in variants:
        read = np.concatenate(logits[variant])
        print(f"{name}: scale {variant[0]:.2f} shift {variant[1]:+.2f}: AUC {_auc(front, read):.3f}, "
              f"read right {np.mean((read > 0) == front):.3f} ({len(front)} people, {front.mean():.2f} from the front)")


def renders(bundle: Path, dataset: Path) -> None:
    reader = FacingReader((bundle / "models" / "facing.onnx").read_bytes(), 2)
    variants = [(scale, 0.0) for scale in SCALES]
    logits: dict = {variant: [] for variant in variants}
    front: list[bool] = []
    for region in read_manifest(dataset).get("regions", {}):
        for sample in open_region(dataset, region).held_out:
            boxes, labels = [], []
            for annotation in sample.annotations:
                x, y, width, height = annotation["amodal_bbox"]
                if height < shipped.MIN_HEIGHT_PX or annotation["bbox"][3] < shipped.MIN_VISIBLE_SHARE * height:
                    continue
                seen = shipped.seen_from_front(annotation)
                if seen is not None:
                    boxes.append([x, y, x + width, y + height])
                    labels.append(seen)
            if boxes:
                image = read_image(sample.image_path)
                front += labels
                for variant in variants:
                    logits[variant].append(reader.read(image, moved(np.array(boxes), *variant)).front_logits)
    report("held-out renders", variants, logits, np.array(front, bool))


def real(bundle: Path, camera: str, detections: Path, cache: Path) -> None:
    reader = FacingReader((bundle / "models" / "facing.onnx").read_bytes(), 2)
    video, frames = CHOOSING[camera]
    ours = {json.loads(line)["frame"]: json.loads(line)["people"] for line in detections.open()}
    yolo = json.loads(cache.read_text())
    variants = [(scale, 0.0) for scale in SCALES] + [(1.0, shift) for shift in SHIFTS]
    logits: dict = {variant: [] for variant in variants}
    front: list[bool] = []
    for frame in FrameSource(Path(video), frames):
        boxes, labels = [], []
        for person in ours.get(frame.number, []):
            if person["score"] < 0.5:
                continue
            best = max(yolo.get(str(frame.number), []), key=lambda row: _iou(person["box"], row[0]), default=None)
            if best is None or _iou(person["box"], best[0]) < 0.5 or not yolo_facing(best[2]):
                continue
            boxes.append(person["box"])
            labels.append(yolo_facing(best[2]) > 0)
        if boxes:
            front += labels
            for variant in variants:
                logits[variant].append(reader.read(frame.image, moved(np.array(boxes, float), *variant)).front_logits)
    report(f"real people, {camera}", variants, logits, np.array(front, bool))


if __name__ == "__main__":
    if sys.argv[1] == "renders":
        renders(Path(sys.argv[2]), Path(sys.argv[3]))
    else:
        real(Path(sys.argv[2]), sys.argv[3], Path(sys.argv[4]), Path(sys.argv[5]))
