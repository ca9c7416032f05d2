"""People hidden behind a nearer person, carried by their track for longer than people lost in the open (frozen
experiment, issue 57 item 2).

    PYTHONPATH=../../src python hidden.py CAMERA ARM BUNDLE --seed S -o results     # CAMERA: pets or tud

Why: TUD-Stadtmitte's people in groups that the bundles miss stand behind a found person, their box a median 0.91
covered by nearer people's ([second-look](../2026-12-03-second-look/)); no network formulation tried has found them
at a precision worth reporting. Most of them were seen before, apart, and have a track. Today the tracker carries
any track unseen for up to ``coast_s`` (0.5 s) at a score falling by ``exp(-t / 1 s)``, and ends it after
``max_gap_s`` (1 s), whether the person was hidden or has gone: a longer memory for every track traded PETS09's
identities against TUD-Stadtmitte's crowd ([identities-at-the-real-rate](../2026-12-02-identities-at-the-real-rate/)).
A track whose predicted box a nearer seen person covers is the one case where the frame itself says why the person
is not seen: they are behind that person. Such a track is kept and reported longer; every other track is treated
as today.

An unseen track is **hidden** in a frame when a person seen in it, standing nearer (their box's bottom below the
track's predicted one), covers at least ``HIDDEN_COVER`` of the track's predicted box. A hidden track ends after
``hidden_gap_s`` rather than ``max_gap_s``, is reported up to ``hidden_coast_s`` rather than ``coast_s``, its score
falling by ``exp(-t / hidden_decay_s)``, and is a duplicate of a seen person (not reported) only where their feet
also meet (within ``gate_heights``): the person hiding them has a box that overlaps theirs by design.

Arms (``ARM``): ``today``; ``hidden_G_D`` (carried and kept up to G s, decay D s). Writes
``results/CAMERA_ARM/seedS_HALF.json``; a finished file is not run again.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

import vc.evaluation.real_video as real_video
from vc.deploy.boxes import box_iou, foot_points
from vc.deploy.tracking import Tracker

_SPEC = importlib.util.spec_from_file_location(
    "winter_measure", Path(__file__).parent.parent / "2026-12-04-winter-clothing" / "measure.py")
winter_measure = sys.modules["winter_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(winter_measure)

HIDDEN_COVER = 0.5  # share of the track's predicted box a nearer seen person covers
SETTINGS = {"hidden_gap_s": 1.0, "hidden_coast_s": 0.5, "hidden_decay_s": 1.0}


def _covered(box: np.ndarray, seen_boxes: np.ndarray) -> float:
    """The largest share of ``box`` one seen box standing nearer (its bottom lower) covers."""
    nearer = seen_boxes[seen_boxes[:, 3] > box[3]]
    if not len(nearer):
        return 0.0
    low = np.maximum(nearer[:, :2], box[:2])
    high = np.minimum(nearer[:, 2:], box[2:])
    overlap = np.prod(np.clip(high - low, 0, None), axis=1)
    return float(overlap.max() / max(np.prod(box[2:] - box[:2]), 1e-9))


class HiddenTracker(Tracker):
    """:class:`vc.deploy.tracking.Tracker` with tracks hidden behind a nearer person kept and carried longer."""

    def update(self, people, time_s, frame=None):
        """Today's update, its tracks first ended here: a hidden one after ``hidden_gap_s``, any other after
        ``max_gap_s``; today's expiry inside it then keeps what this kept."""
        config = self.config
        self.tracks = [t for t in self.tracks if time_s - t.times[-1] <= config.max_gap_s
                       or (getattr(t, "hidden", False) and time_s - t.times[-1] <= SETTINGS["hidden_gap_s"])]
        self.config = replace(config, max_gap_s=max(config.max_gap_s, SETTINGS["hidden_gap_s"]))
        try:
            return super().update(people, time_s, frame)
        finally:
            self.config = config

    def _carried(self, unseen, seen_boxes, time_s):
        config = self.config
        carried = []
        for track in unseen:
            elapsed = time_s - track.times[-1]
            if track.observations < config.coast_min_observations:
                continue
            shift = track.shift(time_s)
            box = track.boxes[-1] + shift
            track.hidden = len(seen_boxes) > 0 and _covered(box, seen_boxes) >= HIDDEN_COVER
            reach, decay = ((SETTINGS["hidden_coast_s"], SETTINGS["hidden_decay_s"]) if track.hidden
                            else (config.coast_s, config.coast_score_decay_s))
            if elapsed > reach:
                continue
            if len(seen_boxes):
                same = box_iou(box[None], seen_boxes)[0] > config.coast_duplicate_iou
                if track.hidden:
                    heights = np.maximum(seen_boxes[:, 3] - seen_boxes[:, 1], 1.0)
                    feet = np.hypot(*(foot_points(seen_boxes) - foot_points(box[None])[0]).T) / heights
                    same &= feet <= config.gate_heights
                if same.any():
                    continue
            last = track.last
            keypoints = last.keypoints.copy()
            keypoints[:, :2] += foot_points(shift)[0]
            carried.append(replace(last, score=last.score * float(np.exp(-elapsed / decay)), box=box,
                                   keypoints=keypoints, mask=np.zeros((0, 0), bool), mask_origin=(0, 0),
                                   coasted=True))
        return carried


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=("pets", "tud"))
    parser.add_argument("arm")
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    if args.arm != "today":
        _, gap, decay = args.arm.split("_")
        SETTINGS.update(hidden_gap_s=max(float(gap), 1.0), hidden_coast_s=float(gap), hidden_decay_s=float(decay))
        real_video.Tracker = HiddenTracker
    halves = winter_measure.recheck.CAMERAS[args.camera]["halves"]
    for half in args.halves:
        path = args.out / f"{args.camera}_{args.arm}" / f"seed{args.seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = winter_measure.measure(args.camera, args.bundle, halves[half], Path(scratch))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{args.camera} {args.arm} seed {args.seed} {half}: tracked {result['ap50_tracked']:.4f} "
              f"groups {result['recall_by_group']} mota {result['tracking']['mota']} idf1 {result['tracking']['idf1']}",
              flush=True)


if __name__ == "__main__":
    main()
