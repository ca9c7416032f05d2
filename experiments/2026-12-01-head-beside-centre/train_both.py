"""One network with a head map and a size map beside today's centre map (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python train_both.py RUN RENDERS REGION -o OUT [--fine-budget | --as-shipped]

The region's network trained as RUN's checkpoint was (same config, renders and seed) with today's targets, except
two of the four fine centre maps (which only train the network; the decoder does not read them): the first learns
each person's log amodal height in :data:`SIZE_UNIT` cells over the cells they cover most (mask-weighed L1, in the
offsets' term), the second a Gaussian at each person's head (the middle of their labelled nose, eyes and ears,
seen or hidden; sigma :data:`HEAD_SIGMA` of their height), whose squared error weighs as the centre map's (with
``--fine-budget``, the head map and the two fine maps kept share the weight today's four fine maps have). The
centre offsets stay today's (to the amodal centre, in the person's heights): at a head, offset x size is the way to
the person's centre. ``--as-shipped`` trains with today's targets: the control, which reproduces the compile's
network bit for bit. Writes OUT/checkpoints/REGION.pt.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).parent.parent / "2026-12-01-visible-anchor"))
import anchors  # noqa: E402

import vc.model.codec as codec  # noqa: E402
import vc.model.data as data_module  # noqa: E402
import vc.model.loss as loss_module  # noqa: E402
from vc.deploy.heatmaps import FINE_CENTRE_CHANNELS, MASK_CHANNEL, input_to_cells  # noqa: E402
from vc.model.trainer import RegionTrainer, load_checkpoint  # noqa: E402
from vc.render.dataset import open_region  # noqa: E402

SIZE_UNIT = 20.0
HEAD_SIGMA = 0.05
SIZE_CHANNEL = FINE_CENTRE_CHANNELS.start
HEAD_CHANNEL = FINE_CENTRE_CHANNELS.start + 1
FINE_KEPT = slice(FINE_CENTRE_CHANNELS.start + 2, FINE_CENTRE_CHANNELS.stop)

#: What the head map and the fine maps kept weigh together (1: each as today's centre map; 0.5 with
#: ``--fine-budget``: together as today's fine map).
FINE_SHARE = [1.0]
_ENCODE = codec.encode
_TERMS = loss_module.heatmap_terms


def encode(annotations, instances, config):
    targets = _ENCODE(annotations, instances, config)
    anchors._draw_sizes(targets[SIZE_CHANNEL], annotations, instances, config.stride)
    heads = targets[HEAD_CHANNEL:HEAD_CHANNEL + 1]
    heads[:] = 0.0
    for annotation in annotations:
        if annotation.get("center") is None:
            continue
        size_cells = annotation["amodal_bbox"][3] / config.stride
        codec._draw_gaussians(heads, np.array([0]), input_to_cells([anchors.head_point(annotation)], config.stride),
                              max(HEAD_SIGMA * size_cells, config.min_sigma_cells))
    return targets


def heatmap_terms(prediction, targets):
    terms = _TERMS(prediction, targets)
    head = (prediction[:, HEAD_CHANNEL] - targets[:, HEAD_CHANNEL]).square().mean()
    terms["fine_centre"] = (head + (prediction[:, FINE_KEPT] - targets[:, FINE_KEPT]).square().mean()) * FINE_SHARE[0]
    size = (prediction[:, SIZE_CHANNEL] - targets[:, SIZE_CHANNEL]).abs() * targets[:, MASK_CHANNEL]
    terms["centre_offsets"] = terms["centre_offsets"] + size.mean()
    return terms


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    parser.add_argument("-o", "--out", type=Path, required=True)
    parser.add_argument("--fine-budget", action="store_true")
    parser.add_argument("--as-shipped", action="store_true", help="today's targets: the control, trained again")
    args = parser.parse_args()
    FINE_SHARE[0] = 0.5 if args.fine_budget else 1.0
    checkpoint = load_checkpoint(args.run / "checkpoints" / f"{args.region}.pt")
    if not checkpoint.config.codec.fine_centre:
        raise SystemExit(f"{args.run}: {args.region}'s network has no fine centre map to carry the head and size")
    if not args.as_shipped:
        anchors.SIZE_UNIT_CELLS[0] = SIZE_UNIT
        data_module.encode = encode
        loss_module.heatmap_terms = heatmap_terms
    data = open_region(args.renders, args.region, checkpoint.config.held_out_fraction)
    RegionTrainer(data, checkpoint.config, args.out, args.renders, device=torch.device("cpu"), workers=1).train()


if __name__ == "__main__":
    main()
