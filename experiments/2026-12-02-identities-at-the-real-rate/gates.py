"""Does the tracker keep PETS09's identities at the clip's real rate (decision 0046) with wider association gates or
a longer memory? IDF1, AP50 tracked and pose agreement tracked, both halves (frozen; 0046's lead).

    PYTHONPATH=src:experiments/2026-12-02-small-people-voted \
        python experiments/2026-12-02-identities-at-the-real-rate/gates.py BUNDLE SEED CAMERA >> results/arms.jsonl

At 10 frames/s PETS09's seed 0 keeps identities worse on the choosing half than at 7 (IDF1 0.706 against 0.782): the
association gate, 0.15 heights plus 1.5 heights a second of the time between sightings, is 0.30 heights a frame
at 10 frames/s and 0.36 at 7. Each arm is the shipped tracker (main at 8f734c5) with one setting changed. Each frame
runs once through the bundle as shipped; every arm's tracker is fed a copy of its people. Scored as vc-eval scores:
AP50 (vc.evaluation.metrics.evaluate), the tracks' IDF1 and identity switches at the operating point
(vc.evaluation.tracks), pose agreement with YOLO11n-pose @1280 (vc.evaluation.agreement).
"""

from __future__ import annotations

import copy
import json
import sys
from pathlib import Path

import arms as voted  # experiments/2026-12-02-small-people-voted/arms.py: data, reference, halves
import numpy as np

from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.misses import operating_point
from vc.evaluation.mot import read_mot_boxes, read_mot_ids
from vc.evaluation.tracks import FrameTracks, track_accuracy

ARMS = {"as shipped": TrackingConfig(),
        "a gate of 0.25 heights": TrackingConfig(gate_heights=0.25),
        "2.5 heights a second": TrackingConfig(max_speed_heights_per_s=2.5),
        "a track kept 2 s unseen": TrackingConfig(max_gap_s=2.0)}


def half(bundle: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = voted.DATA[camera]
    truth, ids = read_mot_boxes(Path(gt)), read_mot_ids(Path(gt))
    reference = YoloPoseOnnx(Path(voted.REFERENCE), threads=2)
    trackers = {name: Tracker(config) for name, config in ARMS.items()}
    scored: dict[str, list[ImageResult]] = {name: [] for name in ARMS}
    tracks: dict[str, list[np.ndarray]] = {name: [] for name in ARMS}
    theirs, numbers = [], []
    with Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above) as run:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = run.run(frame.image)
            tracked = {name: result.reported(tracker.update(copy.deepcopy(result.people), frame.number / fps,
                                                            frame.image))
                       for name, tracker in trackers.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            numbers.append(frame.number)
            for name, people in tracked.items():
                scored[name].append(voted._image(boxes, people))
                tracks[name].append(np.array([p.track for p in people], int))
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    readings = {}
    for name, images in scored.items():
        threshold = operating_point(images).threshold
        accuracy = track_accuracy([FrameTracks(image.truth_boxes, ids.get(number, np.zeros(0, int)), image.boxes,
                                               image.scores, frame_tracks)
                                   for image, number, frame_tracks in zip(images, numbers, tracks[name], strict=True)],
                                  threshold)
        readings[name] = {"ap50": round(evaluate(images).ap50, 4), "idf1": round(accuracy.idf1, 4),
                          "id_switches": accuracy.id_switches, "mota": round(accuracy.mota, 4),
                          "pose": round(pose_agreement(images, theirs).overall, 4)}
    return readings


def main() -> None:
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    for name, (first, last, step) in zip(voted.HALVES, voted.DATA[camera][3], strict=True):
        readings = half(bundle, camera, first, last, step)
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera, "half": name,
                          "frames": [first, last, step], **readings}), flush=True)


if __name__ == "__main__":
    main()
