"""Held-out renders: which of the people overlapping another get a decoded centre of their own (frozen; decision 0033).

    PYTHONPATH=../.. python own_centres.py RUN RENDERS REGION      # e.g. a compile's run/ and renders/, r0

The region's trained network (RUN/checkpoints/REGION.pt) on its held-out samples, decoded as deployment decodes:
a person overlapping another (IoU >= 0.1) has a centre of their own when a decoded centre lies within 0.15 of
their height of theirs and nearer theirs than any other person's. For those without: the centre map's value
there and the distance to the nearest other person's centre, in their heights.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch

from vc.calibration.camera import camera_from_dict
from vc.deploy.decode import decode
from vc.deploy.heatmaps import CENTRE_CHANNEL, input_to_cells
from vc.evaluation.metrics import grouped
from vc.evaluation.renders import image_result
from vc.model.codec import expected_height_map
from vc.model.network import ScenePoseNet
from vc.model.trainer import load_checkpoint
from vc.render.dataset import open_region, read_sample

OWN_CENTRE_REACH = 0.15  # person heights: the decoder's min_centre_separation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    args = parser.parse_args()
    checkpoint = load_checkpoint(args.run / "checkpoints" / f"{args.region}.pt")
    config = checkpoint.config
    net = ScenePoseNet(config.network)
    net.load_state_dict(checkpoint.content["model"])
    net.eval()
    data = open_region(args.renders, args.region, config.held_out_fraction)
    heights = expected_height_map(camera_from_dict(data.region["camera"]), config.codec.stride,
                                  checkpoint.content["reference_height_m"])
    people = with_own = 0
    values, separations = [], []
    for sample in data.held_out:
        image, instances = read_sample(sample)
        with torch.no_grad():
            maps = net(torch.from_numpy(image[None]).permute(0, 3, 1, 2).float() / 255.0)["heatmaps"][0].numpy()
        decoded = decode(maps, config.decode, heights)
        result = image_result(sample.annotations, instances, decoded, config.codec.stride)
        truth = np.asarray(result.truth_boxes, float).reshape(-1, 4)
        centres = np.array([annotation["center"] for annotation in sample.annotations]).reshape(-1, 2)
        tall = truth[:, 3] - truth[:, 1]
        owned = set()
        for person in decoded:
            distance = np.hypot(*(centres - person.centre).T) / tall
            if distance.size and distance.min() < OWN_CENTRE_REACH:
                owned.add(int(np.argmin(distance)))
        for index in np.flatnonzero(grouped(truth) & ~result.ignored()):
            people += 1
            if index in owned:
                with_own += 1
                continue
            column, row = np.round(input_to_cells([centres[index]], config.codec.stride)[0]).astype(int)
            centre_map = maps[CENTRE_CHANNEL]
            values.append(float(centre_map[max(row - 1, 0):row + 2, max(column - 1, 0):column + 2].max(initial=0.0)))
            others = np.delete(centres, index, axis=0)
            separations.append(float((np.hypot(*(others - centres[index]).T) / tall[index]).min()))
    values, separations = np.array(values), np.array(separations)
    print(f"{args.region}: {people} held-out people overlapping another, {with_own} ({with_own / people:.3f}) with a "
          f"decoded centre of their own")
    print(f"  without: centre map there, 10/25/50/75/90 %: {np.percentile(values, [10, 25, 50, 75, 90]).round(2)}")
    print(f"  without: nearest other centre (heights), 10/25/50/75/90 %: "
          f"{np.percentile(separations, [10, 25, 50, 75, 90]).round(2)}; within {OWN_CENTRE_REACH}: "
          f"{np.mean(separations < OWN_CENTRE_REACH):.3f}")


if __name__ == "__main__":
    main()
