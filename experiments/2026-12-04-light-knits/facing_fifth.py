"""A winter bundle's facing model trained again on a fifth of the people of the default-wardrobe renders of the same
scene and seed, shipped in a copy of the bundle in place of its own (frozen experiment, issue 57 item 4).

    PYTHONPATH=../../src python facing_fifth.py WINTER_BUNDLE MIXED_RENDERS OUT --seed S \
        --report results/fifth_CAMERA_seedS.json

Why: the winter bundles with their seed's default-wardrobe facing model read TUD-Stadtmitte's pose better than
either compile (0053). A winter compile could render a small default-wardrobe set for its facing model; a fifth of
the renders is what issue 57's 1.2x compile time allows. A fifth of the people of the full set, drawn with ``seed``,
stands in for a fifth of the samples (the same scene's people, a fifth as many). The classifier, the face turn and the
head's colours are trained as a compile trains them, held out on the full set's held-out people.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

import numpy as np

from vc.deploy.bundle import sha256
from vc.model.export import export_facing
from vc.model.facing import (
    FacingCrops,
    PersonCrops,
    TurnCrops,
    dataset_crops,
    train_face_turn,
    train_facing,
    train_head_colours,
)

SHARE = 0.2


def _share(crops: PersonCrops, rng: np.random.Generator) -> PersonCrops:
    facing = rng.permutation(len(crops.facing))[:round(len(crops.facing) * SHARE)]
    turn = rng.permutation(len(crops.turn))[:round(len(crops.turn) * SHARE)]
    return PersonCrops(FacingCrops(crops.facing.crops[facing], crops.facing.front[facing]),
                       TurnCrops(crops.turn.crops[turn], crops.turn.across[turn]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--report", type=Path, required=True)
    args = parser.parse_args()
    train, held_out = dataset_crops(args.renders)
    train = _share(train, np.random.default_rng(args.seed))
    facing = train_facing(train.facing, held_out.facing, args.seed, show_progress=False)
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
    report = {"renders": str(args.renders), "seed": args.seed, "share": SHARE, "facing": facing.to_dict(),
              "face_turn": turn.to_dict(), "head_colours": head.to_dict()}
    args.report.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
