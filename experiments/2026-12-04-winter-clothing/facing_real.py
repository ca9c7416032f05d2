"""Which way each real person of TUD-Stadtmitte faces, read by the facing models of several bundles on the truth's
boxes, against the way YOLO11n-pose @1280's shoulders and hips put them (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python facing_real.py NAME=BUNDLE ... -o results/facing_real.json [--crops DIR]

Why: the winter compile's facing model reads TUD-Stadtmitte's people the other way round more often than the
default compile's, and both read their own renders equally well. Read on the same boxes (no detector in between),
who does each model get wrong, and what do those people look like? A person counts where the reference finds them
(IoU >= 0.5 with the truth's box) and its shoulders and hips say front or behind clearly: the image-x of the left
ones minus the right ones, over the box's width, at least ``MIN_SPREAD`` with every one of the four confident.
``--crops`` writes sheets of real people's crops to look at: they are the dataset's images, never committed.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.facing import FacingReader, crop_rois
from vc.deploy.frames import FrameSource
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.mot import read_mot_boxes
from vc.keypoints import COCO_KEYPOINTS

FRAMES = Path("../../../shared/data/tud_stadtmitte/frames")
TRUTH = Path("../../../shared/data/tud_stadtmitte/gt_world.txt")
REFERENCE = Path("../../../shared/baselines/yolo11n-pose-1280.onnx")
HALVES = {"choosing": (1, 90), "confirming": (91, 179)}
MIN_SPREAD, MIN_CONFIDENCE = 0.15, 0.5
_LEFT = [COCO_KEYPOINTS.index(name) for name in ("left_shoulder", "left_hip")]
_RIGHT = [COCO_KEYPOINTS.index(name) for name in ("right_shoulder", "right_hip")]


def reference_front(keypoints: np.ndarray, box: np.ndarray) -> int | None:
    """1 seen from the front, 0 from behind, None where the reference's torso does not say clearly."""
    if (keypoints[_LEFT + _RIGHT, 2] < MIN_CONFIDENCE).any():
        return None
    spread = (keypoints[_LEFT, 0].mean() - keypoints[_RIGHT, 0].mean()) / max(box[2] - box[0], 1.0)
    return None if abs(spread) < MIN_SPREAD else int(spread > 0)


def _right(people: list[dict], name: str) -> float:
    """The share of ``people`` the model ``name`` reads the reference's way."""
    return round(float(np.mean([(p["logits"][name] > 0) == p["front"] for p in people])), 3) if people else 0.0


def _by_identity(people: list[dict], name: str) -> dict:
    """How many people (identities) a model reads the other way most of the time, and the three it reads so most."""
    wrong: dict[int, list[bool]] = {}
    for p in people:
        wrong.setdefault(p["id"], []).append((p["logits"][name] > 0) != p["front"])
    return {"people": len(wrong), "mostly_wrong": int(sum(np.mean(w) > 0.5 for w in wrong.values())),
            "worst_3": [{"id": identity, "wrong": int(np.sum(w)), "of": len(w)} for identity, w in
                        sorted(wrong.items(), key=lambda item: -np.sum(item[1]))[:3]]}


def report(people: list[dict], names: list[str]) -> dict:
    """Per half: the share each model reads right, over all readings and seen from the front / behind, by person."""
    out = {}
    for half, (first, last) in HALVES.items():
        inside = [p for p in people if first <= p["frame"] <= last]
        out[half] = {"people": len(inside), "right": {name: _right(inside, name) for name in names},
                     "identities": {name: _by_identity(inside, name) for name in names},
                     "agree": round(float(np.mean([len({p["logits"][n] > 0 for n in names}) == 1 for p in inside])), 3)}
        for front, side in ((1, "front"), (0, "behind")):
            group = [p for p in inside if p["front"] == front]
            out[half][side] = {"people": len(group), "right": {name: _right(group, name) for name in names}}
    return out


def write_crops(people: list[dict], names: list[str], folder: Path) -> None:
    """Sheets of the crops that one model alone reads the other way, seen from the front and from behind."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        wrong = [p for p in people if (p["logits"][name] > 0) != p["front"]
                 and all((p["logits"][other] > 0) == p["front"] for other in names if other != name)]
        for front, side in ((1, "front"), (0, "behind")):
            group = [p["crop"] for p in wrong if p["front"] == front][::3][:24]
            if group:
                sheet = np.concatenate(group + [np.zeros_like(group[0])] * (-len(group) % 12), axis=1)
                sheet = np.concatenate(np.split(sheet, max(len(sheet[0]) // (48 * 12), 1), axis=1), axis=0)
                cv2.imwrite(str(folder / f"only_{name}_wrong_{side}.png"), sheet[:, :, ::-1])


def read_people(readers: dict[str, FacingReader]) -> list[dict]:
    """Every truth box the reference matches and puts clearly front or behind, with each model's front logit."""
    reference = YoloPoseOnnx(REFERENCE, threads=2)
    truth = read_mot_boxes(TRUTH)
    rows = np.loadtxt(TRUTH, delimiter=",", ndmin=2)
    identities = {int(number): rows[rows[:, 0] == number, 1].astype(int) for number in np.unique(rows[:, 0])}
    people = []
    for frame in FrameSource(FRAMES):
        boxes = truth.get(frame.number, np.zeros((0, 4)))
        if not len(boxes) or frame.number > HALVES["confirming"][1]:
            continue
        seen = reference(frame.image)
        if not len(seen.boxes):
            continue
        overlap = box_iou(boxes, seen.boxes)
        logits = {name: reader.read(frame.image, boxes).front_logits for name, reader in readers.items()}
        rois = crop_rois(boxes)
        for index in range(len(boxes)):
            match = int(overlap[index].argmax())
            front = reference_front(seen.keypoints[match], seen.boxes[match])
            if overlap[index, match] < 0.5 or front is None:
                continue
            x0, y0, x1, y1 = (int(round(v)) for v in rois[index])
            crop = frame.image[max(y0, 0):y1, max(x0, 0):x1]
            people.append({"frame": frame.number, "id": int(identities[frame.number][index]), "front": front,
                           "logits": {name: float(value[index]) for name, value in logits.items()},
                           "crop": cv2.resize(crop, (48, 96)) if crop.size else np.zeros((96, 48, 3), np.uint8)})
    return people


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundles", nargs="+", help="NAME=BUNDLE")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--crops", type=Path, help="write the crops each model alone reads the other way (PNG)")
    args = parser.parse_args()
    readers = {}
    for name, path in (item.split("=", 1) for item in args.bundles):
        manifest = json.loads((Path(path) / "manifest.json").read_text())
        readers[name] = FacingReader((Path(path) / manifest["facing"]["model"]).read_bytes(), threads=2)
    people = read_people(readers)
    summary = report(people, list(readers))
    args.out.write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps(summary, indent=1))
    if args.crops:
        write_crops(people, list(readers), args.crops)


if __name__ == "__main__":
    main()
