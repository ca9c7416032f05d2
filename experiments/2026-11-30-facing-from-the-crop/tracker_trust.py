"""The facing arm's bundles tracked with the walk deciding wherever there is one (TrackingConfig.trust_network 1.0:
the facing model's confidence never overrides a walk), against today's 0.3 (frozen, issue 57 item 4).

    PYTHONPATH=. python experiments/2026-11-30-facing-from-the-crop/tracker_trust.py BUNDLE VIDEO GT FRAMES OUT \
        [--fps F]
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
    parser.add_argument("--fps", type=float)
    parser.add_argument("--yolo", type=Path, default=YOLO)
    args = parser.parse_args()
    request = EvaluationRequest(args.bundle, args.video, args.gt, args.out, FrameRange.parse(args.frames), hog=False,
                                externals=(ExternalModel(args.yolo),), threads=1,
                                tracking=TrackingConfig(trust_network=1.0), fps=args.fps)
    report = evaluate_bundle(request, show_progress=False)
    print(args.out, report.metrics["pose_agreement"]["agreement"]["visual compiler"]["overall"])


if __name__ == "__main__":
    main()
