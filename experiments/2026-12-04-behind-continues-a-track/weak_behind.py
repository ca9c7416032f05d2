"""The people behind each peak (``../2026-12-03-second-person/``) given to the tracker as weak people: reported only
where they continue a track seen before, not on their own (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src:../2026-12-03-second-person python weak_behind.py ARM BUNDLE -o results [--threshold T] \
        [--weak] [--seed S] [--halves choosing confirming]

Why: each centre peak can also read the person behind it, and on the held-out renders the maps find 0.83 of the
people overlapping another (0.61 without), but their score fires on most people in front, whether or not anyone
stands behind them, so reported as people they halve the precision of everyone reported on TUD-Stadtmitte. A person
who walks behind another was mostly seen before, apart, and has a track. The tracker already takes weak people (peaks
under the threshold) only where they continue such a track (ByteTrack's idea); an added person at the front person's
peak where nobody stands behind finds no track to continue, and is dropped.

``ARM``: results go to ``results/ARM/seedS_HALF.json`` (``--seed S``, the bundle's compile seed); a finished file
is not run again. ``--threshold``: the behind score that adds a person (none: the maps are not read). ``--weak``:
the added people are weak (continue a track or are dropped), else they are reported as people. Each half is
``vc-eval``'s evaluation (tracked and each frame on its own, the miss analysis), then everyone the tracker reports
each frame, as an appliance reports them, counted against the truth: precision and recall.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import real
import second_person

import vc.deploy.decode as decoding
import vc.deploy.runtime as runtime_module
from vc.deploy.decode import UPRIGHT_PRIOR
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.deploy.tracking import Tracker, TrackingConfig
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.mot import read_mot_boxes

VIDEO = Path("../../../shared/data/tud_stadtmitte/frames")
GROUND_TRUTH = Path("../../../shared/data/tud_stadtmitte/gt_world.txt")
HALVES = {"choosing": "1:90", "confirming": "91:179"}
FPS = 25.0
WEAK = [False]


def decode_weak_behind(heatmaps, config, expected_height_px=None, weak_above=None, prior=UPRIGHT_PRIOR):
    """``second_person.decode_behind`` with the people it adds flagged weak where ``WEAK`` says so."""
    people = second_person.decode_behind(heatmaps, config, expected_height_px, weak_above, prior)
    if not WEAK[0] or heatmaps.shape[0] != second_person.BEHIND_CHANNELS or second_person.THRESHOLD[0] is None:
        return people
    front = len(second_person._DECODE(heatmaps, config, expected_height_px, weak_above, prior))
    return people[:front] + [replace(person, weak=True) for person in people[front:]]


def _peaks_inside(heatmap, threshold, limit=None):
    """``second_person``'s peaks, then the people behind them kept inside the map: an offset can carry a person
    behind one at the map's edge beyond it, where the decoder would index outside the map (or wrap round, below
    zero). The centre map's own peaks are left as the decoder finds them."""
    own = len(second_person._FIND_PEAKS(heatmap, threshold, limit))
    peaks = second_person._find_peaks_behind(heatmap, threshold, limit)
    height, width = heatmap.shape[-2:]
    return peaks[:own] + [(value, np.clip(centre, 0, [width - 1, height - 1])) for value, centre in peaks[own:]]


def reported(bundle: Path, frames: str) -> dict:
    """Everyone the tracker reports each frame of ``frames``, against the truth: precision, recall, and recall of
    the people overlapping another."""
    truth = read_mot_boxes(GROUND_TRUTH)
    config = TrackingConfig()
    tracker = Tracker(config)
    images = []
    with Runtime(bundle, threads=2, weak_people_above=config.weak_people_above) as runtime:
        for frame in FrameSource(VIDEO, FrameRange.parse(frames)):
            result = runtime.run(frame.image)
            people = result.reported(tracker.update(result.people, frame.number / FPS, frame.image))
            images.append(ImageResult(truth_boxes=truth.get(frame.number, np.zeros((0, 4))),
                                      boxes=np.array([p.box for p in people]).reshape(-1, 4),
                                      scores=np.array([p.score for p in people])))
    evaluation = evaluate(images)
    detections = sum(len(image.scores) for image in images)
    matched = sum(len(pairs) for pairs in evaluation.matches)
    return {"reported": detections, "found": matched, "annotated": evaluation.ground_truth,
            "precision": round(matched / max(detections, 1), 4), "recall": round(matched / evaluation.ground_truth, 4),
            "overlapping": evaluation.overlapping, "recall_overlapping": round(evaluation.recall_overlapping, 4)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm")
    parser.add_argument("bundle", type=Path)
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--threshold", type=float)
    parser.add_argument("--weak", action="store_true")
    parser.add_argument("--halves", nargs="*", default=list(HALVES))
    parser.add_argument("--seed", type=int, default=0, help="the compile seed of BUNDLE (names the result files)")
    args = parser.parse_args()
    real.install()
    decoding.find_peaks = _peaks_inside
    runtime_module.decode = decode_weak_behind
    second_person.THRESHOLD[0] = args.threshold
    WEAK[0] = args.weak
    for half in args.halves:
        path = args.out / args.arm / f"seed{args.seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = real.crowd_measure.measure(args.bundle, HALVES[half], Path(scratch))
        result["everyone_reported"] = reported(args.bundle, HALVES[half])
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{args.arm} seed {args.seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
              f"{result['ap50_each_frame']:.4f} reported {result['everyone_reported']}", flush=True)


if __name__ == "__main__":
    main()
