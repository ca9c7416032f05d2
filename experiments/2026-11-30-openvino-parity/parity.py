"""Do a bundle's graphs give the same people under OpenVINO as under onnxruntime? (frozen, issue 59)

Every frame of ``--frames`` through two runtimes of one bundle, each frame on its own, scene fitness as shipped:
``engine="onnxruntime"`` and ``engine="openvino"``. Per frame, the people are matched greedily by box IoU (best
first). Reported: frames where the counts differ, people matched at IoU 0.5, and over the matched people the median,
95th percentile and largest of their box-corner and keypoint differences (px, the largest coordinate of each person)
and score difference; the heat maps' largest difference per region; the milliseconds per frame of each; with
``--gt``, each engine's AP50 against it (every annotated person, no ignore regions: the engines' difference is
the point, not the protocol's number).

    PYTHONPATH=. python experiments/2026-11-30-openvino-parity/parity.py BUNDLE --video V --frames 1:400:5 \
        [--gt GT] --out OUT
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.deploy.runtime import Runtime
from vc.evaluation.metrics import ImageResult, evaluate
from vc.evaluation.mot import read_mot_boxes


def matched(first: list, second: list) -> list[tuple]:
    """Pairs (a, b) of people matched by box IoU >= 0.5, best first, each used once."""
    if not first or not second:
        return []
    ious = box_iou(np.array([p.box for p in first]), np.array([p.box for p in second]))
    pairs, used_a, used_b = [], set(), set()
    for index in np.argsort(-ious, axis=None):
        a, b = np.unravel_index(index, ious.shape)
        if ious[a, b] < 0.5:
            break
        if a in used_a or b in used_b:
            continue
        used_a.add(a), used_b.add(b)
        pairs.append((first[a], second[b]))
    return pairs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--video", type=Path, required=True)
    parser.add_argument("--frames", type=FrameRange.parse, required=True)
    parser.add_argument("--gt", type=Path, default=None, help="ground truth, MOT text format")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    runtimes = {engine: Runtime(args.bundle, threads=args.threads, engine=engine)
                for engine in ("onnxruntime", "openvino")}
    counts_differ, people, pairs_found = 0, {engine: 0 for engine in runtimes}, 0
    box, keypoint, score = [], [], []
    heatmaps = {runner.entry.name: 0.0 for runner in runtimes["onnxruntime"].runners}
    milliseconds = {engine: [] for engine in runtimes}
    frames, truth, results = 0, read_mot_boxes(args.gt) if args.gt else None, {engine: [] for engine in runtimes}
    for frame in FrameSource(args.video, args.frames):
        found = {}
        for engine, runtime in runtimes.items():
            start = time.perf_counter()
            found[engine] = runtime(frame.image)
            milliseconds[engine].append(1e3 * (time.perf_counter() - start))
            people[engine] += len(found[engine])
            if truth is not None:
                results[engine].append(ImageResult(
                    truth.get(frame.number, np.zeros((0, 4))), np.array([p.box for p in found[engine]]).reshape(-1, 4),
                    np.array([p.score for p in found[engine]])))
        for ours, theirs in zip(runtimes["onnxruntime"].runners, runtimes["openvino"].runners, strict=True):
            difference = np.abs(ours.heatmaps(frame.image) - theirs.heatmaps(frame.image)).max()
            heatmaps[ours.entry.name] = max(heatmaps[ours.entry.name], float(difference))
        counts_differ += len(found["onnxruntime"]) != len(found["openvino"])
        for a, b in matched(found["onnxruntime"], found["openvino"]):
            pairs_found += 1
            box.append(float(np.abs(a.box - b.box).max()))
            keypoint.append(float(np.abs(a.keypoints[:, :2] - b.keypoints[:, :2]).max()))
            score.append(abs(a.score - b.score))
        frames += 1
    report = {"bundle": str(args.bundle), "precision": runtimes["onnxruntime"].bundle.manifest["precision"],
              "frames": frames, "people": people, "frames_with_other_counts": counts_differ,
              "people_matched_iou_0_5": pairs_found,
              **{f"{name}_difference_{label}": float(f"{np.percentile(values, q):.3g}") if values else None
                 for name, values in (("box_px", box), ("keypoint_px", keypoint), ("score", score))
                 for label, q in (("median", 50), ("p95", 95), ("max", 100))},
              "largest_heatmap_difference": {name: float(f"{value:.3g}") for name, value in heatmaps.items()},
              "ap50": ({engine: round(evaluate(values).ap50, 4) for engine, values in results.items()}
                       if truth else None),
              "ms_per_frame_median": {engine: round(float(np.median(values[1:])), 1)
                                      for engine, values in milliseconds.items()}}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "parity.json").write_text(json.dumps(report, indent=1) + "\n")
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
