"""The facing model trained on the people of several render sets, half of each set's crops (as many as one set
holds), shipped in a copy of a bundle in place of its own (frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python facing_mix.py BUNDLE OUT RENDERS [RENDERS ...] [--seed S]

Why: a TUD-Stadtmitte compile in winter coats finds more people and reads their facing worse than the compile in
the default wardrobe, and its region networks with the default compile's facing model read pose as well as that
compile (``results/pose_hybrids.jsonl``). Does a facing model that sees both wardrobes read real people as the
default one does? The classifier, the face turn and the head's colours are trained as a compile trains them
(:func:`vc.stages.train.train_facing_model`), on each set's crops subsampled by ``seed``.
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
    _joined,
    dataset_crops,
    train_face_turn,
    train_facing,
    train_head_colours,
)


def _half(crops: PersonCrops, rng: np.random.Generator) -> PersonCrops:
    facing = rng.permutation(len(crops.facing))[:len(crops.facing) // 2]
    turn = rng.permutation(len(crops.turn))[:len(crops.turn) // 2]
    return PersonCrops(FacingCrops(crops.facing.crops[facing], crops.facing.front[facing]),
                       TurnCrops(crops.turn.crops[turn], crops.turn.across[turn]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bundle", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("renders", type=Path, nargs="+")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    sets = [dataset_crops(renders) for renders in args.renders]
    train = _joined([_half(train, rng) for train, _ in sets])
    held_out = _joined([held for _, held in sets])
    facing = train_facing(train.facing, held_out.facing, args.seed)
    turn = train_face_turn(train.turn, held_out.turn, args.seed)
    head = train_head_colours(train.facing, held_out.facing, args.seed)
    shutil.copytree(args.bundle, args.out)
    manifest = json.loads((args.out / "manifest.json").read_text())
    model = export_facing(facing.net, turn.net, head.net)
    (args.out / manifest["facing"]["model"]).write_bytes(model)
    manifest["facing"].update(model_sha256=sha256(model), held_out_accuracy=facing.to_dict()["held_out_accuracy"])
    (args.out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    print(json.dumps({"renders": [str(r) for r in args.renders], "train_crops": len(train.facing),
                      "facing": facing.to_dict(), "face_turn": turn.to_dict(), "head": head.to_dict()}))


if __name__ == "__main__":
    main()
