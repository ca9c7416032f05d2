"""A bundle evaluated by vc-eval with two tracker options (frozen, issue 57; decision record 0028), on the tracker
of ``tracker_arms.patch`` (both options, off by default, on top of 1185074):

* ``--size-gate G``: a person continues a track only if their box height differs from the track's last by at most
  G (log of the ratio) plus 0.5 a second since (not kept);
* ``--max-walk-growth W``: the walk does not decide the facing of a person whose box grows or shrinks faster than W
  (log height a second; kept at 0.4 as ``TrackingConfig.max_walk_growth_per_s``).

    git apply experiments/2026-11-30-a-walk-that-is-not-a-walk/tracker_arms.patch   # on 1185074's tracking.py
    PYTHONPATH=. python experiments/2026-11-30-a-walk-that-is-not-a-walk/tracker_arms.py BUNDLE VIDEO GT FRAMES OUT \
        --size-gate G [--max-walk-growth W] [--fps F]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import EvaluationRequest, ExternalModel, evaluate_bundle

YOLO = Path("/work/shared/baselines/yolo11n-pose-1280.onnx")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("bundle", type=Path)
    parser.add_argument("video", type=Path)
    parser.add_argument("gt", type=Path)
    parser.add_argument("frames")
    parser.add_argument("out", type=Path)
    parser.add_argument("--size-gate", type=float, required=True)
    parser.add_argument("--max-walk-growth", type=float, default=float("inf"))
    parser.add_argument("--fps", type=float)
    parser.add_argument("--yolo", type=Path, default=YOLO)
    args = parser.parse_args()
    request = EvaluationRequest(args.bundle, args.video, args.gt, args.out, FrameRange.parse(args.frames), hog=False,
                                externals=(ExternalModel(args.yolo),), threads=1,
                                tracking=TrackingConfig(size_gate=args.size_gate,
                                                        max_walk_growth_per_s=args.max_walk_growth), fps=args.fps)
    report = evaluate_bundle(request, show_progress=False)
    tracked = report.metrics["detectors"]["visual compiler"]["ap50"]
    print(args.out, f"AP50 tracked {tracked:.4f}", report.metrics["tracking"].get("accuracy"))


if __name__ == "__main__":
    main()
