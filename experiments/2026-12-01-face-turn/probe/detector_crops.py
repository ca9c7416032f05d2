"""Crops cut from the boxes a bundle's own region networks draw on its compile's renders, matched to the rendered
people (IoU >= 0.5, score >= 0.3), labelled by where each face points (frozen probe of decision 0038).

    PYTHONPATH=. python experiments/2026-12-01-face-turn/probe/detector_crops.py BUNDLE RENDERS OUT.npz [front]

A face points to the image's right (True) or left (False) when the rendered nose stands at least 0.03 of the
person's height from the ears' midpoint; people nearer along the view are left out. With ``front``, the label is
the facing classifier's instead (seen from the front: True; :func:`vc.model.facing.seen_from_front`). OUT holds
``train_crops``, ``train_front`` (the label, named as harness.py of 2026-11-30-facing-camera-look names it), and the
held-out pair.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import onnxruntime as ort

from vc.deploy.decode import DecodeConfig
from vc.deploy.facing import FRAME_INPUT, ROIS_INPUT, crop_rois
from vc.io import read_image
from vc.model import facing as shipped
from vc.model.precision import evaluate_model
from vc.render.dataset import open_region


def points_right(annotation: dict) -> bool | None:
    points = np.reshape(annotation["keypoints"], (-1, 3))
    if points[0, 2] <= 0 or points[3, 2] <= 0 or points[4, 2] <= 0:
        return None
    offset = (points[0, 0] - (points[3, 0] + points[4, 0]) / 2) / annotation["amodal_bbox"][3]
    return None if abs(offset) < 0.03 else bool(offset > 0)


def overlaps(box: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    width = np.minimum(box[2], boxes[:, 2]) - np.maximum(box[0], boxes[:, 0])
    height = np.minimum(box[3], boxes[:, 3]) - np.maximum(box[1], boxes[:, 1])
    inter = np.clip(width, 0, None) * np.clip(height, 0, None)
    return inter / ((box[2] - box[0]) * (box[3] - box[1]) + (boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])
                    - inter)


def main() -> None:
    bundle, renders, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    label_of = shipped.seen_from_front if sys.argv[4:] == ["front"] else points_right
    manifest = json.loads((bundle / "manifest.json").read_text())
    cut = ort.InferenceSession(shipped.crop_graph().SerializeToString(), providers=["CPUExecutionProvider"])
    parts: dict[str, tuple[list, list]] = {"train": ([], []), "held_out": ([], [])}
    counts = {"matched": 0, "unmatched": 0}
    for entry in manifest["regions"]:
        data = open_region(renders, entry["name"])
        model = (bundle / entry["model"]).read_bytes()
        heights = np.load(bundle / entry["expected_height"])
        config = DecodeConfig(**entry["decode"])
        for split, samples in (("train", data.train), ("held_out", data.held_out)):
            found = evaluate_model(model, samples, tuple(entry["crop_window"][2:]), config, heights, False)
            for sample, image in zip(samples, found.images, strict=True):
                boxes, labels, taken = [], [], set()
                for annotation in sample.annotations:
                    x, y, width, height = annotation["amodal_bbox"]
                    if height < shipped.MIN_HEIGHT_PX or annotation["bbox"][3] < shipped.MIN_VISIBLE_SHARE * height:
                        continue
                    label = label_of(annotation)
                    if label is None:
                        continue
                    if not len(image.boxes):
                        counts["unmatched"] += 1
                        continue
                    iou = overlaps(np.array([x, y, x + width, y + height]), image.boxes)
                    iou[list(taken)] = 0.0
                    best = int(np.argmax(iou))
                    if iou[best] < 0.5 or image.scores[best] < 0.3:
                        counts["unmatched"] += 1
                        continue
                    taken.add(best)
                    counts["matched"] += 1
                    boxes.append(image.boxes[best])
                    labels.append(label)
                if boxes:
                    crops = cut.run(None, {FRAME_INPUT: read_image(sample.image_path)[None],
                                           ROIS_INPUT: crop_rois(np.array(boxes))})[0]
                    parts[split][0].append(np.clip(np.rint(crops.transpose(0, 2, 3, 1) * 255), 0, 255)
                                           .astype(np.uint8))
                    parts[split][1].extend(labels)
    np.savez_compressed(out, **{f"{split}_crops": np.concatenate(crops) for split, (crops, _) in parts.items()},
                        **{f"{split}_front": np.array(labels) for split, (_, labels) in parts.items()})
    print(out, {split: len(labels) for split, (_, labels) in parts.items()}, counts)


if __name__ == "__main__":
    main()
