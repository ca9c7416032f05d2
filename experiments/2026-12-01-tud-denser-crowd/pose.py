"""Pose agreement with YOLO11n-pose @1280 for the denser-crowd arm: each bundle on each half, tracked and each frame on
its own (frozen experiment, decision 0032).

    PYTHONPATH=../.. python pose.py ARM B0 B1 B2 -o results      # writes results/ARM/pose_seedS_HALF.json
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from measure import TUD

from vc.deploy.frames import FrameRange
from vc.deploy.tracking import TrackingConfig
from vc.evaluation.real_video import EvaluationRequest, ExternalModel, evaluate_bundle

YOLO = TUD["video"].parents[2] / "baselines" / "yolo11n-pose-1280.onnx"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm")
    parser.add_argument("bundles", type=Path, nargs="+", help="one per compile seed, in seed order")
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    for half in ("choosing", "confirming"):
        for seed, bundle in enumerate(args.bundles):
            path = args.out / args.arm / f"pose_seed{seed}_{half}.json"
            if path.exists():
                continue
            with tempfile.TemporaryDirectory() as scratch:
                request = EvaluationRequest(bundle=bundle, video=TUD["video"], ground_truth=TUD["gt"],
                                            output=Path(scratch), frames=FrameRange.parse(TUD["halves"][half]),
                                            hog=False, externals=(ExternalModel(YOLO.resolve()),), threads=2,
                                            tracking=TrackingConfig(), fps=TUD["fps"])
                agreement = evaluate_bundle(request, show_progress=False).metrics["pose_agreement"]["agreement"]
            overall = {name: value["overall"] for name, value in agreement.items()}
            path.write_text(json.dumps(overall, indent=1) + "\n")
            print(args.arm, seed, half, overall, flush=True)


if __name__ == "__main__":
    main()
