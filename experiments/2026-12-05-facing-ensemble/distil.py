"""One facing classifier trained to read as three members' mean reads (distilled), shipped in a copy of the compile's
bundle in place of its own classifier (frozen experiment, issue 57 item 4): the members' reading at one network's
time?

    PYTHONPATH=../../src python distil.py RENDERS BUNDLE OUT --seed S

The members are the facing classifier trained as a compile trains it from seeds S, S+1000 and S+2000
(``vc.model.facing.train_facing``). The student is a classifier of the same size trained the same way from seed S,
its target each crop's mean probability of being seen from the front over the members (read on the crop as
rendered), not the label. The face turn and the head's colours are the compile's, trained again from seed S (the
same weights). Only the facing model differs from BUNDLE's.
"""

from __future__ import annotations

import argparse
import json
import shutil
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn

from vc.deploy.bundle import sha256
from vc.model import facing as model
from vc.model.export import export_facing


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("renders", type=Path)
    parser.add_argument("bundle", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    args = parser.parse_args()
    start = time.perf_counter()
    train, held_out = model.dataset_crops(args.renders)
    members = [model.train_facing(train.facing, held_out.facing, seed, show_progress=False)
               for seed in (args.seed, args.seed + 1000, args.seed + 2000)]
    soft = np.mean([1.0 / (1.0 + np.exp(-model._outputs(member.net, train.facing.crops))) for member in members],
                   axis=0)
    torch.manual_seed(args.seed)
    student = model.FacingNet()
    model._fit(student, train.facing.crops, soft, nn.BCEWithLogitsLoss(), 1.0, args.seed, model.EPOCHS, False,
               "student")
    turn = model.train_face_turn(train.turn, held_out.turn, args.seed, show_progress=False)
    head = model.train_head_colours(train.facing, held_out.facing, args.seed)
    facing_model = export_facing(student, turn.net, head.net)
    if args.out.exists():
        shutil.rmtree(args.out)
    shutil.copytree(args.bundle, args.out)
    manifest = json.loads((args.out / "manifest.json").read_text())
    (args.out / manifest["facing"]["model"]).write_bytes(facing_model)
    accuracy = model.accuracy(student, held_out.facing)
    manifest["facing"].update(model_sha256=sha256(facing_model), held_out_accuracy=accuracy)
    (args.out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    report = {"seed": args.seed, "student_held_out_accuracy": accuracy,
              "members_held_out_accuracy": [member.held_out_accuracy for member in members],
              "members_mean_agreement_with_labels": float(((soft > 0.5) == train.facing.front).mean()),
              "seconds": round(time.perf_counter() - start, 1)}
    print(json.dumps(report), flush=True)


if __name__ == "__main__":
    main()
