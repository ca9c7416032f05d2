"""Does a walking person face where they walk? The premise of :mod:`vc.deploy.tracking`, checked on a real
camera's ground-truth tracks against a pose model trained on real photos.

    python experiments/2026-11-25-facing-and-handedness/facing_from_motion.py --video V --gt GT.txt
        --external POSE_MODEL.onnx [--frames 1:400:5] [--fps F] [--half-window-s 0.3]
        --out experiments/2026-11-25-facing-and-handedness/results

For every ground-truth person in the selected frames whom the reference model (a YOLO-pose ONNX model) detects
(score >= 0.5, IoU >= 0.5) with both shoulders confident (>= 0.5) and apart (at least 5 % of the box height, so
that a side view, whose facing the shoulders cannot tell, is left out), the reference's facing — seen from
behind when the left shoulder is on the image's left — is compared with what the person's ground-truth track
says: seen from behind when their feet (box bottom) move up the image over ``half_window_s`` either side of the
frame. The share that agrees is reported overall and by how much of the motion is along the person's axis (up
or down the image) against across it. The reference errs too (a proxy, like the pose agreement of
:mod:`vc.evaluation.agreement`): the share is a floor on how often the premise holds.

Writes ``facing_from_motion.json`` and ``facing_from_motion.md`` to ``--out``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from tqdm import tqdm

from vc.deploy.boxes import box_iou
from vc.deploy.frames import FrameRange, FrameSource
from vc.evaluation.baselines import YoloPoseOnnx
from vc.evaluation.mot import read_mot_boxes, read_mot_ids
from vc.io import write_json
from vc.keypoints import COCO_KEYPOINTS

LEFT_SHOULDER, RIGHT_SHOULDER = COCO_KEYPOINTS.index("left_shoulder"), COCO_KEYPOINTS.index("right_shoulder")
CONFIDENT = 0.5
SIDE_VIEW = 0.05  # shoulders closer than this many box heights in x: a side view
#: |motion along the axis| / |motion across it|: the buckets reported.
BUCKETS = ((0.0, 0.25), (0.25, 0.5), (0.5, 1.0), (1.0, float("inf")))


def reference_facing(boxes: np.ndarray, keypoints: np.ndarray, truth_box: np.ndarray) -> int:
    """+1 (seen from behind), -1 (from the front) or 0 (not detected, shoulders unsure or a side view) of the
    reference's detection matching ``truth_box``."""
    if not len(boxes):
        return 0
    overlaps = box_iou(truth_box[None], boxes)[0]
    best = int(np.argmax(overlaps))
    left, right = keypoints[best, LEFT_SHOULDER], keypoints[best, RIGHT_SHOULDER]
    if overlaps[best] < 0.5 or min(left[2], right[2]) < CONFIDENT:
        return 0
    dx = right[0] - left[0]
    if abs(dx) < SIDE_VIEW * (truth_box[3] - truth_box[1]):
        return 0
    return 1 if dx > 0 else -1


def track_motion(track: dict[int, np.ndarray], frame: int, half: int) -> tuple[float, float] | None:
    """The feet's motion (across, along: down the image positive) in box heights between ``half`` frames before
    and after ``frame``; None where the track does not span them."""
    before, after = track.get(frame - half), track.get(frame + half)
    if before is None or after is None:
        return None
    height = track[frame][3] - track[frame][1]
    return (((after[0] + after[2]) - (before[0] + before[2])) / 2 / height, (after[3] - before[3]) / height)


def measure(video: Path, gt: Path, reference: Path, frames: FrameRange, fps: float, half_window_s: float) -> dict:
    model = YoloPoseOnnx(reference)
    tracks: dict[int, dict[int, np.ndarray]] = {}  # person -> frame -> box
    for (number, boxes), ids in zip(read_mot_boxes(gt).items(), read_mot_ids(gt).values(), strict=True):
        for box, person in zip(boxes, ids, strict=True):
            tracks.setdefault(int(person), {})[number] = box
    half = max(1, round(half_window_s * fps))
    rows = []  # (reference facing, along, across)
    source = FrameSource(video, frames)
    for frame in tqdm(source, total=len(source), desc="reference", unit="frame"):
        present = [(track, track[frame.number]) for track in tracks.values() if frame.number in track]
        if not present:
            continue
        detections = model(frame.image)
        confident = np.asarray(detections.scores).ravel() >= CONFIDENT
        boxes = np.asarray(detections.boxes).reshape(-1, 4)[confident]
        for track, box in present:
            facing = reference_facing(boxes, np.asarray(detections.keypoints)[confident], box)
            motion = track_motion(track, frame.number, half)
            if facing and motion is not None and motion[1] != 0.0:
                rows.append((facing, motion[1], motion[0]))
    table = np.array(rows).reshape(-1, 3)
    agrees = np.where(table[:, 1] < 0, 1, -1) == table[:, 0]
    ratio = np.abs(table[:, 1]) / np.maximum(np.abs(table[:, 2]), 1e-9)
    buckets = {}
    for low, high in BUCKETS:
        inside = (ratio >= low) & (ratio < high)
        buckets[f"{low:g}-{high:g}"] = {"people": int(inside.sum()),
                                         "agreement": round(float(agrees[inside].mean()), 4) if inside.any() else None}
    selection = f"{frames.first}:{frames.last or ''}:{frames.step}"
    return {"video": str(video), "ground_truth": str(gt), "reference": str(reference), "frames": selection,
            "fps": fps, "half_window_s": half_window_s, "half_window_frames": half,
            "people": len(table), "agreement": round(float(agrees.mean()), 4) if len(table) else None,
            "seen_from_behind_share": round(float((table[:, 0] > 0).mean()), 4) if len(table) else None,
            "by_along_over_across": buckets}


def _table(result: dict) -> str:
    lines = [f"Facing from walking direction against {Path(result['reference']).name} "
             f"({result['people']} people, {result['video']}, frames {result['frames']}, "
             f"motion over ±{result['half_window_s']} s)", "",
             "| motion along / across the axis | people | agreement |", "|---|---|---|"]
    lines += [f"| {name} | {value['people']} | {value['agreement']} |"
              for name, value in result["by_along_over_across"].items()]
    lines.append(f"| all | {result['people']} | {result['agreement']} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--video", type=Path, required=True, help="video file or folder of frames")
    parser.add_argument("--gt", type=Path, required=True, help="ground truth with person ids, MOT text format")
    parser.add_argument("--external", type=Path, required=True, help="the reference YOLO-pose ONNX model")
    parser.add_argument("--frames", type=FrameRange.parse, default=FrameRange())
    parser.add_argument("--fps", type=float, default=None, help="frames per second (default: the video's)")
    parser.add_argument("--half-window-s", type=float, default=0.3, help="motion measured this long either side")
    parser.add_argument("--out", type=Path, required=True, help="output folder")
    args = parser.parse_args(argv)
    source = FrameSource(args.video, args.frames)
    fps = args.fps or (source.fps if source.kind == "video" else None)
    if fps is None:
        parser.error("a folder of frames needs --fps")
    result = measure(args.video, args.gt, args.external, args.frames, fps, args.half_window_s)
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "facing_from_motion.json", result)
    (args.out / "facing_from_motion.md").write_text(_table(result))
    print(_table(result), end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
