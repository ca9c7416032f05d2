"""The crop network's keypoints on real people, against YOLO11n-pose @1280 as vc-eval compares them (frozen).

    PYTHONPATH=src:.:experiments/2026-12-01-keypoint-crops python experiments/2026-12-01-keypoint-crops/real.py \
        BUNDLE NET.pt CAMERA FIRST LAST STEP [FPS] >> OUT.jsonl

The bundle finds its people as shipped (each frame on its own, or tracked over every frame with FPS, as vc-eval
does). Each person found is cut from the frame around their box as ``crops.py`` cuts renders, and the crop network
reads their keypoints. Its pairs are in image order; each person takes them in the order that lies nearest the
bundle's own keypoints over all pairs together, so the bundle's facing (its facing model, or the walk) stays what
orders them. Arms: the bundle's keypoints as shipped; the network's for the limbs (elbows, wrists, knees, ankles);
for the body (shoulders down); for all 17. Each is scored as shipped and with the pairs in the reference's order
(the pose-ceiling experiment's reading, repeated here), which leaves the keypoints' places alone.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import crops as C
import numpy as np
import torch

from vc.deploy.facing import crop_rois
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.heatmaps import PAIRS, swap_pairs
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, REFERENCE_CONFIDENCE, matched_people, pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import HEAD_FRACTION_OF_HEIGHT, ImageResult
from vc.evaluation.mot import read_mot_boxes
from vc.keypoints import COCO_KEYPOINTS

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt")}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"

ARMS = {
    "limbs": [COCO_KEYPOINTS.index(f"{side}_{part}") for part in ("elbow", "wrist", "knee", "ankle")
              for side in ("left", "right")],
    "body": list(range(5, 17)),
    "all": list(range(17)),
}


def in_bundle_order(read: np.ndarray, bundle: np.ndarray) -> np.ndarray:
    """The crop network's image-ordered keypoints (17, 3) in the order nearest the bundle's (17, 3), over all pairs."""
    exchanged = swap_pairs(read, [True] * len(PAIRS))
    members = [k for pair in PAIRS for k in pair]
    cost = [np.linalg.norm(option[members, :2] - bundle[members, :2], axis=1).sum() for option in (read, exchanged)]
    return read if cost[0] <= cost[1] else exchanged


def refined(net: C.CropPoseNet, image: np.ndarray, people: list) -> list[np.ndarray]:
    if not people:
        return []
    rois = crop_rois(np.array([person.box for person in people]))
    crops = np.stack([C.cut(image, roi) for roi in rois])
    read = C.predict(net, crops)
    out = []
    for person, roi, points in zip(people, rois, read, strict=True):
        frame_points = points.copy()
        frame_points[:, :2] = C.to_frame(points[:, :2], roi)
        out.append(in_bundle_order(frame_points, person.keypoints))
    return out


def reading(ours: list, theirs: list, order: bool) -> dict:
    """Pose agreement of ``ours`` with ``theirs`` (vc.evaluation.agreement); with ``order``, each person's pairs
    exchanged where more keypoints then agree (the pose-ceiling experiment's reading)."""
    images = []
    for mine, reference, my_matches, their_matches in zip(ours, theirs, matched_people(ours), matched_people(theirs),
                                                          strict=True):
        keypoints = mine.keypoints.copy()
        for truth in set(my_matches) & set(their_matches) if order else ():
            person, ref = keypoints[my_matches[truth]], reference.keypoints[their_matches[truth]]
            height = mine.truth_boxes[truth][3] - mine.truth_boxes[truth][1]
            confident = ref[:, 2] >= REFERENCE_CONFIDENCE
            exchanged = swap_pairs(person, [True] * len(PAIRS))
            agree = [(np.linalg.norm(k[:, :2] - ref[:, :2], axis=1)
                      <= AGREEMENT_HEAD_SIZES * HEAD_FRACTION_OF_HEIGHT * height)[confident].sum()
                     for k in (person, exchanged)]
            keypoints[my_matches[truth]] = exchanged if agree[1] > agree[0] else person
        images.append(ImageResult(truth_boxes=mine.truth_boxes, boxes=mine.boxes, scores=mine.scores,
                                  keypoints=keypoints))
    agreement = pose_agreement(images, theirs)
    return {"overall": round(agreement.overall, 4), "people": agreement.people,
            "per_keypoint": {name: round(value, 3) for name, value in agreement.per_keypoint().items()}}


def main() -> None:
    bundle, weights, camera = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    frames = FrameRange(*map(int, sys.argv[4:7]))
    fps = float(sys.argv[7]) if len(sys.argv) > 7 else None
    torch.set_num_threads(2)
    state = torch.load(weights)
    net = C.CropPoseNet(tuple(state[f"{name}.0.0.weight"].shape[0] for name in
                              ("to_half", "to_quarter", "to_eighth", "sixteenth")))
    net.load_state_dict(state)
    video, gt = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    tracker = Tracker(TrackingConfig()) if fps else None
    ours = {name: [] for name in ("as shipped", *ARMS)}
    theirs = []
    seen = FrameRange(frames.first, frames.last, 1) if fps else frames
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above if fps else None) as runtime:
        for frame in FrameSource(Path(video), seen):
            result = runtime.run(frame.image)
            if tracker:
                people = result.reported(tracker.update(result.people, frame.number / fps, frame.image))
                if (frame.number - frames.first) % frames.step:
                    continue
            else:
                people = [person for person in result.people if not person.weak]
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            shipped = np.array([p.keypoints for p in people]).reshape(-1, 17, 3)
            read = np.array(refined(net, frame.image, people)).reshape(-1, 17, 3)
            for name, keypoints in (("as shipped", []), *ARMS.items()):
                mixed = shipped.copy()
                mixed[:, keypoints, :2] = read[:, keypoints, :2]
                ours[name].append(ImageResult(truth_boxes=boxes, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                                              scores=np.array([p.score for p in people]), keypoints=mixed))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    print(json.dumps({"bundle": str(bundle), "net": str(weights), "camera": camera,
                      "frames": [frames.first, frames.last, frames.step], "tracked_fps": fps,
                      **{name: {"as read": reading(images, theirs, False),
                                "pairs in the reference's order": reading(images, theirs, True)}
                         for name, images in ours.items()}}))


if __name__ == "__main__":
    main()
