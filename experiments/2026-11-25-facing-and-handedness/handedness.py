"""Whether a trained run learned which way people face: its handedness maps against the rendered truth.

    python experiments/2026-11-25-facing-and-handedness/handedness.py RUN DATASET [--samples 100]
        [--out experiments/2026-11-25-facing-and-handedness/results/pose_handedness.json]

Each region's network runs on its held-out renders; over the cells a person covers by at least half (the target
mask), the handedness maps (:mod:`vc.deploy.heatmaps`: +1 where a pair's image-left member is the person's left
one, -1 where it is the right one) are compared with the targets drawn by the codec: the share of cells whose
sign matches (0.5 is a coin toss) and the median magnitude of the output against the target's (a network that
cannot tell hedges at zero). A wrong sign exchanges all of a person's left and right keypoints, which is what
real-pose agreement with a reference model then shows (``vc-eval --external``: "left and right the other way
round").
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import torch

from vc.deploy.heatmaps import HANDEDNESS_CHANNELS, MASK_CHANNEL
from vc.io import write_json
from vc.model.codec import encode
from vc.model.export import network_from_checkpoint
from vc.model.trainer import checkpoint_path, load_checkpoint
from vc.render.dataset import open_region, read_manifest, read_sample

#: Cells a person covers by at least this much are compared (the mask target is coverage).
COVERED = 0.5


@torch.no_grad()
def region_handedness(run: Path, dataset: Path, region: str, samples: int) -> dict:
    """Sign agreement and magnitudes of one region's handedness maps on its first ``samples`` held-out renders."""
    checkpoint = load_checkpoint(checkpoint_path(run, region))
    net = network_from_checkpoint(checkpoint).eval()
    predicted, target = [], []
    for sample in open_region(dataset, region).held_out[:samples]:
        image, instances = read_sample(sample)
        maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        truth = encode(sample.annotations, instances, checkpoint.config.codec)
        covered = truth[MASK_CHANNEL] >= COVERED
        predicted.append(maps[HANDEDNESS_CHANNELS][:, covered].ravel())
        target.append(truth[HANDEDNESS_CHANNELS][:, covered].ravel())
    predicted, target = np.concatenate(predicted), np.concatenate(target)
    decided = np.abs(target) >= COVERED  # cells that are one person's, not a mix of two
    return {"cells": int(decided.sum()),
            "sign_agreement": round(float((np.sign(predicted) == np.sign(target))[decided].mean()), 4),
            "median_output_magnitude": round(float(np.median(np.abs(predicted[decided]))), 4),
            "median_target_magnitude": round(float(np.median(np.abs(target[decided]))), 4)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path, help="a vc-train run folder")
    parser.add_argument("dataset", type=Path, help="the vc-render dataset it was trained on")
    parser.add_argument("--samples", type=int, default=100, help="held-out renders per region")
    parser.add_argument("--out", type=Path, help="write the results here (JSON)")
    args = parser.parse_args(argv)
    results = {region: region_handedness(args.run, args.dataset, region, args.samples)
               for region in read_manifest(args.dataset)["regions"]}
    for region, result in results.items():
        print(f"{region}: sign right on {result['sign_agreement']:.0%} of {result['cells']} person cells, "
              f"output {result['median_output_magnitude']:.2f} against targets of "
              f"{result['median_target_magnitude']:.2f}")
    if args.out:
        write_json(args.out, {"run": str(args.run), "dataset": str(args.dataset), "regions": results})
    print(json.dumps({"regions": len(results)}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
