"""Which way a tracked person faces: the walk (the tracker as shipped) against the bundle's facing model, read each
frame or voted over the track (frozen, issue 57 item 4 and its pose acceptance figures).

TUD-Stadtmitte's pose agreement with YOLO11n-pose @1280 is lower tracked than each frame on its own (0.708 against
0.725 on the confirming half): the walk overrules the facing model, which since decisions 0042 and 0043 reads tall
people more often right. The arms, each a tracker fed the same runtime output:

- "control": the tracker as shipped (the walk decides where it is clear, or where the networks hedge).
- "tall: the model": people the facing model reads twice (at least MIRRORED_FROM_PX tall) keep its order; the walk
  decides for the others as before.
- "tall: the track's vote": the same people ordered by the sign of the facing model's handedness averaged over the
  track's window (1 s, the tracker's: the frames it saw them in, this one with them); the walk decides for the
  others.
- "tall: a 3 s vote": the same, the readings of the track's last 3 s voting.
- "tall: the model, unless the walk is clear": this frame's reading where the walk is not clear; a clear walk
  decides (what the vote adds to no longer letting an unclear walk decide).
- "tall: the vote, unless the walk is clear": the vote where the walk is not clear; a clear walk decides.
- "tall: a 3 s vote, unless the walk is clear": the same, over 3 s.
- "everyone: the vote where the walk is unclear": every person the facing model read; a clear walk decides as
  before, elsewhere the track's vote rather than the networks' confidence weighed against an unclear walk.

An earlier vote (../2026-12-01-tracker-cues/vote.py, before decision 0042) ordered only the people whose walk did not
decide as shipped; an unclear walk still decided wherever the networks hedged. Here an unclear walk decides nothing
for the people an arm covers.

Each frame is run once by the bundle as shipped; every tracker gets its own copy of the people, and is scored against
YOLO11n-pose @1280 as vc-eval scores pose (people matched to the same ground truth by both).

    git worktree add /tmp/base 7dd94b0   # the tracker these arms subclass, as it was before decision 0044
    PYTHONPATH=/tmp/base/src python experiments/2026-12-02-facing-over-the-track/arms.py BUNDLE SEED CAMERA both|0|1 \
        >> experiments/2026-12-02-facing-over-the-track/results/arms.jsonl

HALF 0 is the choosing half, 1 the confirming one.
"""

from __future__ import annotations

import copy
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from vc.deploy.facing import MIRRORED_FROM_PX
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Person, Runtime
from vc.deploy.tracking import Tracker, TrackingConfig, facing_pairs, foot_speed
from vc.evaluation.agreement import pose_agreement
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.metrics import ImageResult
from vc.evaluation.mot import read_mot_boxes

DATA = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt",
                 7.0, ((1, 200, 5), (201, 400, 5))),
        "tud": ("../shared/data/tud_stadtmitte/frames", "../shared/data/tud_stadtmitte/gt_world.txt",
                25.0, ((1, 90, 1), (91, 179, 1)))}
REFERENCE = "../shared/baselines/yolo11n-pose-1280.onnx"


def read_by_model(person: Person) -> bool:
    """The facing model ordered this person's pairs (the runtime keeps the networks' confidence aside then)."""
    return person.network_handedness is not None


def tall(person: Person) -> bool:
    return float(person.box[3] - person.box[1]) >= MIRRORED_FROM_PX


class VotingTracker(Tracker):
    """The shipped tracker, with the facing model's handedness kept over each track's window and a rule for whom
    the window's vote orders (``who``: "tall" or "everyone") and whether a clear walk still decides first."""

    def __init__(self, who: str | None, vote: bool, walk_first: bool, vote_s: float = TrackingConfig().window_s
                 ) -> None:
        super().__init__(TrackingConfig())
        self.who, self.vote, self.walk_first, self.vote_s = who, vote, walk_first, vote_s
        self.handedness: dict[int, list[tuple[float, float]]] = {}

    def update(self, people, time_s, frame=None):
        self._now = time_s
        return super().update(people, time_s, frame)

    def _faced(self, person: Person, track) -> Person:
        if self.who is None or not read_by_model(person) or (self.who == "tall" and not tall(person)):
            return super()._faced(person, track)
        window = [(t, h) for t, h in self.handedness.get(track.identity, [])
                  if t >= self._now - self.vote_s] + [(self._now, person.handedness)]
        self.handedness[track.identity] = window
        if self.walk_first and self._walk_is_clear(track):
            return super()._faced(person, track)
        if not self.vote:
            return person
        mean = float(np.mean([h for _, h in window]))
        if mean == 0.0:
            return person
        return replace(person, keypoints=facing_pairs(person, seen_from_behind=mean > 0))

    def _walk_is_clear(self, track) -> bool:
        config = self.config
        if len(track.times) < config.min_observations:
            return False
        boxes, times = np.array(track.boxes), np.array(track.times)
        feet = (boxes[:, 3])
        height = float((boxes[:, 3] - boxes[:, 1]).mean())
        speed, error = foot_speed(times, feet, height, config.foot_jitter_heights)
        heights = np.maximum(boxes[:, 3] - boxes[:, 1], 1.0)
        growth, _ = foot_speed(times, np.log(heights), 1.0, config.foot_jitter_heights)
        return speed != 0.0 and abs(speed) >= config.min_significance * error and \
            abs(growth) <= config.max_walk_growth_per_s


ARMS = {"control": (None, False, False),
        "tall: the model": ("tall", False, False),
        "tall: the track's vote": ("tall", True, False),
        "tall: a 3 s vote": ("tall", True, False, 3.0),
        "tall: the model, unless the walk is clear": ("tall", False, True),
        "tall: the vote, unless the walk is clear": ("tall", True, True),
        "tall: a 3 s vote, unless the walk is clear": ("tall", True, True, 3.0),
        "everyone: the vote where the walk is unclear": ("everyone", True, True)}


def _image(truth: np.ndarray, people: list) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p.box for p in people]).reshape(-1, 4),
                       scores=np.array([p.score for p in people]),
                       keypoints=np.array([p.keypoints for p in people]).reshape(-1, 17, 3))


def half(bundle: Path, camera: str, first: int, last: int, step: int) -> dict:
    video, gt, fps, _ = DATA[camera]
    truth = read_mot_boxes(Path(gt))
    reference = YoloPoseOnnx(Path(REFERENCE), threads=2)
    run = Runtime(bundle, threads=2, weak_people_above=TrackingConfig().weak_people_above)
    trackers = {name: VotingTracker(*rule) for name, rule in ARMS.items()}
    scored: dict[str, list[ImageResult]] = {name: [] for name in ["each frame", *ARMS]}
    theirs: list[ImageResult] = []
    facing_counts: dict[str, dict[str, int]] = {name: {} for name in ARMS}
    try:
        for frame in FrameSource(Path(video), FrameRange(first, last, 1)):
            result = run.run(frame.image)
            tracked = {name: result.reported(tracker.update(copy.deepcopy(result.people), frame.number / fps,
                                                            frame.image))
                       for name, tracker in trackers.items()}
            if (frame.number - first) % step:
                continue
            boxes = truth.get(frame.number, np.zeros((0, 4)))
            scored["each frame"].append(_image(boxes, [p for p in result.people if not p.weak]))
            for name, people in tracked.items():
                scored[name].append(_image(boxes, people))
                for person in people:
                    facing_counts[name][person.facing] = facing_counts[name].get(person.facing, 0) + 1
            found = reference(frame.image)
            theirs.append(ImageResult(truth_boxes=boxes, boxes=found.boxes, scores=found.scores,
                                      keypoints=found.keypoints))
    finally:
        run.close()
    readings = {}
    for name, images in scored.items():
        agreement = pose_agreement(images, theirs)
        readings[name] = {"overall": round(agreement.overall, 4), "people": agreement.people,
                          "swapped": agreement.left_right_swapped,
                          **({"facing": facing_counts[name]} if name in facing_counts else {})}
    return {"frames": [first, last, step], **readings}


def main() -> None:
    bundle, seed, camera = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    halves = DATA[camera][3] if sys.argv[4] == "both" else [DATA[camera][3][int(sys.argv[4])]]
    for first, last, step in halves:
        print(json.dumps({"bundle": str(bundle), "seed": seed, "camera": camera,
                          **half(bundle, camera, first, last, step)}), flush=True)


if __name__ == "__main__":
    main()
