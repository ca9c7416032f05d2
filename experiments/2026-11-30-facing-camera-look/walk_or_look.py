"""When the walk and when the facing model should decide which way a tracked person faces (frozen, issue 57 item 4):
every person a facing bundle reports, tracked over every frame of a half, with what the tracker knew of their walk
and what the facing model read, against YOLO11n-pose @1280's facing on the scored frames.

    PYTHONPATH=. python experiments/2026-11-30-facing-camera-look/walk_or_look.py BUNDLE pets|tud FIRST LAST STEP \
        YOLO_CACHE OUT.npz

Each row: the track's vertical foot speed and its standard error, its horizontal speed (heights per second), the
track's length in the window, the facing model's handedness (> 0 seen from behind) and the networks', and YOLO's
facing (+1 front, -1 behind). Rows are kept only for people YOLO reads clearly (harness.yolo_facing).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from vc.deploy.boxes import foot_points
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Person, Runtime
from vc.deploy.tracking import Tracker, TrackingConfig, foot_speed, tracking_rate

sys.path.insert(0, str(Path(__file__).parent))
from harness import _iou, yolo_facing  # noqa: E402

SOURCES = {"pets": ("../shared/data/pets09_s2l1/vtest.avi", None),
           "tud": ("../shared/data/tud_stadtmitte/frames", 25.0)}


class RecordingTracker(Tracker):
    """Today's tracker, which also keeps what it knew of each person's walk when it decided their facing."""

    def __init__(self, config: TrackingConfig) -> None:
        super().__init__(config)
        self.walks: dict[int, tuple] = {}

    def _faced(self, person: Person, track) -> Person:
        config = self.config
        look = person.handedness  # the facing model's reading (or the networks' without one), before the walk's
        if len(track.times) >= config.min_observations:
            boxes, times = np.array(track.boxes), np.array(track.times)
            feet, height = foot_points(boxes), float((boxes[:, 3] - boxes[:, 1]).sum() / len(boxes))
            speed, error = foot_speed(times, feet[:, 1], height, config.foot_jitter_heights)
            across, _ = foot_speed(times, feet[:, 0], height, config.foot_jitter_heights)
            # the box's growth (log height per second): > 0 coming closer, whatever the camera's height
            growth, growth_error = foot_speed(times, np.log(boxes[:, 3] - boxes[:, 1]), 1.0, config.foot_jitter_heights)
            self.walks[id(person)] = (speed, error, across, len(times), look, growth, growth_error)
        faced = super()._faced(person, track)
        if id(person) in self.walks:
            self.walks[id(faced)] = self.walks[id(person)]
        return faced


def main() -> None:
    bundle, camera, first, last, step, cache, out = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:6]), *sys.argv[6:8]
    video, fps = SOURCES[camera]
    yolo = json.loads(Path(cache).read_text())
    scored = set(range(first, last + 1, step))
    source = FrameSource(Path(video), FrameRange(first, last, 1))
    rate = tracking_rate(source, fps)
    tracker = RecordingTracker(TrackingConfig())
    rows = []
    with Runtime(Path(bundle), threads=1, weak_people_above=tracker.config.weak_people_above) as runtime:
        for frame in source:
            result = runtime.run(frame.image)
            tracker.walks.clear()
            tracked = tracker.update(result.people, frame.number / rate, frame.image)
            if frame.number not in scored:
                continue
            for person in tracked:
                if person.score < 0.5 or person.weak:
                    continue
                best = max(yolo.get(str(frame.number), []), key=lambda row: _iou(person.box, row[0]), default=None)
                if best is None or _iou(person.box, best[0]) < 0.5 or not yolo_facing(best[2]):
                    continue
                speed, error, across, count, look, growth, growth_error = tracker.walks.get(
                    id(person), (0.0, np.inf, 0.0, 0, np.nan, 0.0, np.inf))
                network = person.network_handedness if person.network_handedness is not None else 0.0
                rows.append((frame.number, person.track, speed, error, across, count, look, network,
                             person.facing == "motion", yolo_facing(best[2]), person.box[3] - person.box[1],
                             growth, growth_error))
    np.save(out, np.array(rows, np.float64))
    print(out, len(rows))


if __name__ == "__main__":
    main()
