"""Held-out renders: people overlapping another with a decoded centre of their own, and the renders' AP, for today's
network and the anchored ones (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python held_out_groups.py RUN RENDERS REGION [--checkpoint PT --visible]
        [--separation S --offset-unit U --size-unit U]

RUN/checkpoints/REGION.pt's config and expected heights; ``--checkpoint`` the weights to read instead (a network
trained by ``anchors.py train``), ``--visible`` decodes as :mod:`visible_decode` does (with its options). A person
overlapping another (IoU >= 0.1) has a centre of their own when a decoded centre lies within 0.15 of their height of
their amodal centre and nearer it than any other person's (``../2026-12-01-people-in-front/own_centres.py``'s rule).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch
import visible_decode

import vc.deploy.decode as decoding
from vc.calibration.camera import camera_from_dict
from vc.evaluation.metrics import evaluate, grouped
from vc.evaluation.renders import image_result
from vc.model.codec import expected_height_map
from vc.model.network import ScenePoseNet
from vc.model.trainer import load_checkpoint
from vc.render.dataset import open_region, read_sample

OWN_CENTRE_REACH = 0.15


def _owners(decoded: list, annotations: list[dict], truth: np.ndarray) -> np.ndarray:
    """The annotated people with a decoded centre of their own: each decoded centre's nearest amodal centre, in that
    person's heights, if within :data:`OWN_CENTRE_REACH`."""
    if not decoded or not len(truth):
        return np.zeros(0, int)
    amodal = np.array([annotation["center"] for annotation in annotations], float)  # (N, 2)
    found = np.array([person.centre for person in decoded], float)  # (M, 2)
    scaled = np.linalg.norm(found[:, None] - amodal[None], axis=2) / (truth[:, 3] - truth[:, 1])[None]  # (M, N)
    nearest = scaled.argmin(axis=1)
    return np.unique(nearest[scaled[np.arange(len(found)), nearest] < OWN_CENTRE_REACH])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    parser.add_argument("--checkpoint", type=Path)
    parser.add_argument("--visible", action="store_true")
    parser.add_argument("--separation", type=float, help="with --visible: the anchors' separation (heights)")
    parser.add_argument("--offset-unit", type=float, help="with --visible: the offsets' unit in cells")
    parser.add_argument("--size-unit", type=float, help="with --visible: the size map's unit in cells")
    args = parser.parse_args()
    if args.visible:
        visible_decode.install(separation=args.separation, offset_unit=args.offset_unit,
                               size_unit=args.size_unit)
    checkpoint = load_checkpoint(args.run / "checkpoints" / f"{args.region}.pt")
    config = checkpoint.config
    net = ScenePoseNet(config.network)
    net.load_state_dict(load_checkpoint(args.checkpoint).content["model"] if args.checkpoint
                        else checkpoint.content["model"])
    net.eval()
    data = open_region(args.renders, args.region, config.held_out_fraction)
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.codec.stride,
                                  checkpoint.content["reference_height_m"])
    people = with_own = 0
    results = []
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        decoded = decoding.decode(maps, config.decode, heights)
        result = image_result(sample.annotations, instances, decoded, config.codec.stride)
        results.append(result)
        truth = np.asarray(result.truth_boxes, float).reshape(-1, 4)
        asked = np.flatnonzero(grouped(truth) & ~result.ignored())
        people += len(asked)
        with_own += int(np.isin(asked, _owners(decoded, sample.annotations, truth)).sum())
    summary = evaluate(results)
    print(f"{args.region} {'visible' if args.visible else 'centre'} {args.checkpoint or 'shipped'}: {people} held-out "
          f"people overlapping another, {with_own / people:.3f} with a decoded centre of their own; AP50 "
          f"{summary.ap50:.4f}")


if __name__ == "__main__":
    main()
