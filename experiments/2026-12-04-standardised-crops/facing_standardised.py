"""A winter bundle's facing classifier trained again on its own renders, each crop standardised before the network
sees it (less its mean, over its spread), shipped in a copy of the bundle in place of its own (frozen experiment,
issue 57 item 4).

    PYTHONPATH=../../src python facing_standardised.py WINTER_BUNDLE RENDERS OUT --seed S \
        --report results/standardised_CAMERA_seedS.json

Why: the classifier learns the renders' people exactly and carries less of it to real people than the head's
colours do (0041), and trained on people in coats it reads TUD-Stadtmitte's people worse than trained on the
default wardrobe (0053). The head reader sees each crop's cells standardised: where the crop is lighter or darker,
not how light or dark its clothes and light are. Does the classifier, given each crop the same way, read real people
as it reads renders? The standardisation is part of the network, so the exported model does it on every crop at
runtime too. The face turn and the head's colours are trained as a compile trains them (the same weights).
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from torch import Tensor

from vc.deploy.bundle import sha256
from vc.model import facing as facing_module
from vc.model.export import export_facing
from vc.model.facing import FacingNet, dataset_crops, train_face_turn, train_facing, train_head_colours

#: Added to each crop's spread (crop values run 0-1), as the head reader's floor: a flat crop's noise not inflated.
SPREAD_FLOOR = 4.0 / 255.0


class StandardisedFacingNet(FacingNet):
    """:class:`FacingNet` over each crop less its mean over all pixels and colours, over its spread."""

    def forward(self, crops: Tensor) -> Tensor:
        centred = crops - crops.mean(dim=(1, 2, 3), keepdim=True)
        spread = centred.square().mean(dim=(1, 2, 3), keepdim=True).sqrt()
        return super().forward(centred / (spread + SPREAD_FLOOR))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--report", type=Path, required=True)
    args = parser.parse_args()
    train, held_out = dataset_crops(args.renders)
    facing_module.FacingNet = StandardisedFacingNet  # train_facing builds the module's FacingNet
    facing = train_facing(train.facing, held_out.facing, args.seed, show_progress=False)
    facing_module.FacingNet = FacingNet
    assert isinstance(facing.net, StandardisedFacingNet)
    turn = train_face_turn(train.turn, held_out.turn, args.seed, show_progress=False)
    head = train_head_colours(train.facing, held_out.facing, args.seed)
    if args.out.exists():
        shutil.rmtree(args.out)
    shutil.copytree(args.bundle, args.out)
    manifest = json.loads((args.out / "manifest.json").read_text())
    model = export_facing(facing.net, turn.net, head.net)
    (args.out / manifest["facing"]["model"]).write_bytes(model)
    manifest["facing"].update(model_sha256=sha256(model), held_out_accuracy=facing.to_dict()["held_out_accuracy"])
    (args.out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    report = {"renders": str(args.renders), "seed": args.seed, "standardised": True, "facing": facing.to_dict(),
              "face_turn": turn.to_dict(), "head_colours": head.to_dict()}
    args.report.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
