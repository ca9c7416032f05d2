"""What tells a carried fragment track (a second track on a person who is seen) from a carried person who is hidden
(frozen experiment, issue 57 item 2): every person the tracker carries with the longer carrying of
``../2026-12-05-carried-people`` (``coast_1.0s_iou_0.8``), labelled against the ground truth and described by their
track's history.

    PYTHONPATH=../../src python diagnose.py BUNDLE --label COMPILE [--half choosing] >> results/carried.jsonl

Labels, frame by frame: the people seen are matched to the ground truth first (IoU >= 0.5, highest score first);
a carried person then matching a person left unmatched is ``hidden`` (found by carrying), one matching a person
already matched ``duplicate``, one matching nobody ``false``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.mot import read_mot_boxes

_RECHECK = importlib.util.spec_from_file_location(
    "recheck", Path(__file__).parent.parent / "2026-11-29-decisions-on-halves" / "recheck.py")
recheck = sys.modules["recheck"] = importlib.util.module_from_spec(_RECHECK)
_RECHECK.loader.exec_module(recheck)

LONGER = {"coast_s": 1.0, "coast_duplicate_iou": 0.8}


class DescribedTracker(Tracker):
    """The shipped tracker, keeping for each track when it was born, how much its first box overlapped a person
    seen beside it, and the most its box has overlapped another seen person's in one frame."""

    def __init__(self, config: TrackingConfig) -> None:
        super().__init__(config)
        self.history: dict[int, dict] = {}

    def update(self, people, time_s, frame=None):
        result = super().update(people, time_s, frame)
        seen = [p for p in result if not p.coasted]
        boxes = np.array([p.box for p in seen], np.float64).reshape(-1, 4)
        overlaps = box_iou(boxes, boxes) if len(boxes) else np.zeros((0, 0))
        np.fill_diagonal(overlaps, 0.0)
        for k, person in enumerate(seen):
            beside = float(overlaps[k].max()) if len(seen) > 1 else 0.0
            entry = self.history.setdefault(person.track, {"born": time_s, "born_beside": beside, "most_beside": 0.0,
                                                           "seen": 0})
            entry["most_beside"] = max(entry["most_beside"], beside)
            entry["seen"] += 1
            entry["last_beside"] = beside
        return result


def describe(bundle: Path, half: str, label: str) -> list[dict]:
    settings = recheck.CAMERAS["tud"]
    frames = FrameRange.parse(settings["halves"][half])
    truth = read_mot_boxes(settings["gt"])
    config = replace(TrackingConfig(), **LONGER)
    tracker = DescribedTracker(config)
    rows = []
    with Runtime(bundle, threads=2, weak_people_above=config.weak_people_above) as runtime:
        for frame in FrameSource(settings["video"], FrameRange(frames.first, frames.last, 1)):
            time_s = frame.number / settings["fps"]
            result = runtime.run(frame.image)
            people = result.reported(tracker.update(result.people, time_s, frame.image))
            gt = truth.get(frame.number, np.zeros((0, 4)))
            seen = sorted((p for p in people if not p.coasted), key=lambda p: -p.score)
            matched = set()
            for person in seen:
                if not len(gt):
                    break
                overlaps = box_iou(person.box[None], gt)[0]
                overlaps[list(matched)] = 0.0
                if overlaps.max() >= 0.5:
                    matched.add(int(overlaps.argmax()))
            seen_boxes = np.array([p.box for p in seen], np.float64).reshape(-1, 4)
            for person in (p for p in people if p.coasted):
                overlaps = box_iou(person.box[None], gt)[0] if len(gt) else np.zeros(0)
                best = int(overlaps.argmax()) if len(gt) else -1
                kind = ("false" if best < 0 or overlaps[best] < 0.5 else
                        "duplicate" if best in matched else "hidden")
                history = tracker.history[person.track]
                nearest = (seen[int(box_iou(person.box[None], seen_boxes)[0].argmax())].box if len(seen_boxes)
                           else None)
                track = next(t for t in tracker.tracks if t.identity == person.track)
                rows.append({"compile": label, "half": half, "frame": frame.number, "kind": kind,
                             "score": person.score, "unseen_s": time_s - track.times[-1],
                             "age_s": track.times[-1] - history["born"], "observations": track.observations,
                             "born_beside": history["born_beside"], "most_beside": history["most_beside"],
                             "last_beside": history["last_beside"],
                             "seen_iou_now": float(box_iou(person.box[None], seen_boxes).max())
                             if len(seen_boxes) else 0.0,
                             "height": float(person.box[3] - person.box[1]),
                             # the seen person overlapping it most: their feet below its own (heights), and their
                             # height over its own
                             "feet_below": float((nearest[3] - person.box[3]) / (person.box[3] - person.box[1]))
                             if nearest is not None else None,
                             "height_ratio": float((nearest[3] - nearest[1]) / (person.box[3] - person.box[1]))
                             if nearest is not None else None})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--label", required=True)
    parser.add_argument("--half", default="choosing", choices=["choosing", "confirming"])
    args = parser.parse_args()
    for row in describe(args.bundle, args.half, args.label):
        print(json.dumps(row))


if __name__ == "__main__":
    main()
