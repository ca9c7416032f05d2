"""The region's network trained again exactly as RUN's checkpoint was (same config, renders and seed, this process's
trainer, one loader worker): the control for a network retrained with other targets (frozen experiment).

    PYTHONPATH=../.. python retrain.py RUN RENDERS REGION -o OUT
"""

from __future__ import annotations

import argparse
from pathlib import Path

import torch

from vc.model.trainer import RegionTrainer, load_checkpoint
from vc.render.dataset import open_region


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("region")
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    checkpoint = load_checkpoint(args.run / "checkpoints" / f"{args.region}.pt")
    data = open_region(args.renders, args.region, checkpoint.config.held_out_fraction)
    RegionTrainer(data, checkpoint.config, args.out, args.renders, device=torch.device("cpu"), workers=1).train()


if __name__ == "__main__":
    main()
