"""Which way PETS09's people face, read from where they walk on the ground, against the left and right that the
reference detector and the bundle give them (frozen experiment, issue 57 item 4).

    PYTHONPATH=../.. python facing_by_walk.py BUNDLE EVAL_DIR [EVAL_DIR ...] -o results/facing_by_walk.json

Issue 57 asks the bundle's pose to agree with YOLO11n-pose @1280's, left and right included. Whether the reference
reads left and right right is not known from its agreement. People walk forward: a person walking towards the camera
faces it, and their left shoulder and hip are on the image's right. PETS09 is calibrated, so each annotated person's
feet give their ground track. The truth here is the people whose track over 15 frames (about 2 s) moves at least
0.5 m/s within 45 degrees of straight towards the camera or straight away from it; their facing is read from the
image order of their shoulders and hips (the sum of left minus right x, over those seen with confidence, at least
2 % of the box's height apart). Each detector's people matched to the truth (IoU >= 0.5, every 5th frame of each
EVAL_DIR's frames) are counted: facing read as walked, the other way, or unread. The bundle's people are read each
frame on its own (``Runtime.run``) and tracked (the EVAL_DIR's ``detections.jsonl`` from ``vc-eval``). Also the
mean confidence of the bundle's nose, each frame, for the people walking towards the camera and away: whether the
keypoint maps see a face.
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.baselines import YoloPoseOnnx
from vc.scenes.loader import load_scene

DATA = Path(__file__).resolve().parents[3] / "shared" / "data" / "pets09_s2l1"
SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "pets09_s2l1" / "scene.yaml"
YOLO = DATA.parent.parent / "baselines" / "yolo11n-pose-1280.onnx"
FPS = 7.0  # PETS 2009's frame rate
HALF_WINDOW = 7  # frames each side of the one read
MIN_SPEED = 0.5  # m/s
MIN_COSINE = np.cos(np.radians(45))
TORSO_PAIRS = ((5, 6), (11, 12))  # COCO left/right shoulder, left/right hip
CONFIDENCE = {"YOLO11n-pose@1280": 0.5, "bundle": 0.2}  # the agreement's reference threshold; the decoder's
MIN_SPREAD = 0.02  # of the box height


def tracks(camera, rows: np.ndarray) -> dict[int, dict[int, np.ndarray]]:
    """{person id: {frame: ground xy}} of the annotated people's feet (box bottom middle) in the MOT ``rows``."""
    feet = np.column_stack([rows[:, 2] + rows[:, 4] / 2, rows[:, 3] + rows[:, 5]])
    hit = camera.ground_from_pixels(feet)
    found: dict[int, dict[int, np.ndarray]] = defaultdict(dict)
    for (frame, person), point, ok in zip(rows[:, :2].astype(int), hit.points[:, :2], hit.ok, strict=True):
        if ok:
            found[person][frame] = point
    return found


def walked_facing(track: dict[int, np.ndarray], frame: int, camera_xy: np.ndarray) -> int:
    """+1 walking towards the camera (facing it), -1 away, 0 neither clearly."""
    frames = [f for f in range(frame - HALF_WINDOW, frame + HALF_WINDOW + 1) if f in track]
    if len(frames) < HALF_WINDOW or frame not in track:
        return 0
    points = np.array([track[f] for f in frames])
    velocity = np.polyfit(np.array(frames) / FPS, points, 1)[0]
    speed = np.hypot(*velocity)
    if speed < MIN_SPEED:
        return 0
    towards = camera_xy - track[frame]
    cosine = velocity @ towards / (speed * np.hypot(*towards))
    return 1 if cosine >= MIN_COSINE else -1 if cosine <= -MIN_COSINE else 0


def read_facing(keypoints: np.ndarray, box: np.ndarray, confidence: float) -> int:
    """+1 the left members on the image's right (facing the camera), -1 on its left, 0 unread."""
    spreads = [keypoints[left, 0] - keypoints[right, 0] for left, right in TORSO_PAIRS
               if keypoints[left, 2] >= confidence and keypoints[right, 2] >= confidence]
    spread = sum(spreads) if spreads else 0.0
    return 0 if abs(spread) < MIN_SPREAD * (box[3] - box[1]) else int(np.sign(spread))


def boxes_of(rows: np.ndarray, person_ids: list[int], frame: int) -> np.ndarray:
    """The annotated boxes (x0, y0, x1, y1) of ``person_ids`` in ``frame``, in that order."""
    by_id = {int(row[1]): row[2:6] for row in rows[rows[:, 0] == frame]}
    return np.array([[x, y, x + w, y + h] for x, y, w, h in (by_id[person] for person in person_ids)])


def matched(boxes: np.ndarray, scores: np.ndarray, truth: np.ndarray) -> dict[int, int]:
    """{truth index: detection index}, greedy by score at IoU >= 0.5."""
    pairs: dict[int, int] = {}
    if not len(boxes) or not len(truth):
        return pairs
    overlaps = box_iou(boxes, truth)
    for detection in np.argsort(-scores):
        free = [t for t in np.argsort(-overlaps[detection]) if overlaps[detection, t] >= 0.5 and t not in pairs]
        if free:
            pairs[free[0]] = int(detection)
    return pairs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("evaluations", type=Path, nargs="+", help="vc-eval output folders (their frames are read)")
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    camera = load_scene(SCENE, require_image=False).camera
    rows = np.loadtxt(DATA / "gt_dev_frames_0001-0400.txt", delimiter=",")
    ground = tracks(camera, rows)
    camera_xy = np.asarray(camera.center)[:2]
    reference = YoloPoseOnnx(YOLO, None, 2)
    results = {}
    with Runtime(args.bundle, threads=2) as runtime:
        for folder in args.evaluations:
            metrics = json.loads((folder / "metrics.json").read_text())["frames"]
            frames = FrameRange(metrics["first"], metrics["last"], metrics["step"])
            tracked = {line["frame"]: line["people"] for line in map(json.loads, (folder / "detections.jsonl")
                                                                      .read_text().splitlines())}
            counts = {name: {"as walked": 0, "the other way": 0, "unread": 0,
                             "the other way, walking towards the camera": 0, "walking towards the camera": 0}
                      for name in ("YOLO11n-pose@1280", "bundle, each frame", "bundle, tracked")}
            walkers = 0
            nose = {1: [], -1: []}  # the bundle's nose confidence each frame, by walked facing
            for frame in FrameSource(DATA / "vtest.avi", frames):
                truth_ids = [person for person, track in ground.items() if frame.number in track]
                facing = {person: walked_facing(ground[person], frame.number, camera_xy) for person in truth_ids}
                truth_ids = [person for person in truth_ids if facing[person]]
                if not truth_ids:
                    continue
                walkers += len(truth_ids)
                truth = boxes_of(rows, truth_ids, frame.number)
                yolo = reference(frame.image)
                people = [person for person in runtime.run(frame.image).people if not person.weak]
                readings = {
                    "YOLO11n-pose@1280": (yolo.boxes, yolo.scores, yolo.keypoints, CONFIDENCE["YOLO11n-pose@1280"]),
                    "bundle, each frame": (np.array([p.box for p in people]).reshape(-1, 4),
                                           np.array([p.score for p in people]),
                                           np.array([p.keypoints for p in people]).reshape(-1, 17, 3),
                                           CONFIDENCE["bundle"]),
                    "bundle, tracked": (np.array([p["box"] for p in tracked[frame.number]]).reshape(-1, 4),
                                        np.array([p["score"] for p in tracked[frame.number]]),
                                        np.array([p["keypoints"] for p in tracked[frame.number]]).reshape(-1, 17, 3),
                                        CONFIDENCE["bundle"])}
                for name, (boxes, scores, keypoints, confidence) in readings.items():
                    for index, detection in matched(boxes, scores, truth).items():
                        read = read_facing(keypoints[detection], boxes[detection], confidence)
                        outcome = "unread" if not read else "as walked" if read == facing[truth_ids[index]] \
                            else "the other way"
                        counts[name][outcome] += 1
                        if facing[truth_ids[index]] > 0:
                            counts[name]["walking towards the camera"] += 1
                            counts[name]["the other way, walking towards the camera"] += outcome == "the other way"
                        if name == "bundle, each frame":
                            nose[facing[truth_ids[index]]].append(float(keypoints[detection, 0, 2]))
            results[f"{frames.first}:{frames.last}:{frames.step}"] = {
                "walkers": walkers, "counts": counts,
                "bundle nose confidence, each frame": {"towards the camera": float(np.mean(nose[1])),
                                                       "away": float(np.mean(nose[-1]))}}
            print(frames, walkers, json.dumps(counts), flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
