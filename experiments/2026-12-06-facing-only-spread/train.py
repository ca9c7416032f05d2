"""One compile's renders, its facing model trained again from other training seeds, alone and distilled (frozen
experiment, issue 57 items 1 and 4): how far does pose move when only the facing model is trained again, and how far
does the distilled classifier's difference from the single one move?

    PYTHONPATH=../../src python train.py RENDERS BUNDLE OUT T...

For each training seed T it writes two copies of BUNDLE that differ from it in the facing model alone:
``OUT/singleT/bundle``, the facing model as a compile trains it from seed T (T = the compile's seed gives BUNDLE's
own, byte for byte), and ``OUT/distilledT/bundle``, facing-ensemble's ``distil.py`` from seed T: one classifier
trained on the mean probability of a front of members trained from seeds T, T+1000 and T+2000. Both carry the face
turn and the head's colours trained from seed T, so each pair differs in its classifier alone. Classifiers are kept
in ``OUT/classifiers`` and a finished bundle is kept, so a stopped run resumes.
"""

from __future__ import annotations

import json
import shutil
import sys
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn

from vc.deploy.bundle import sha256
from vc.model import facing as model
from vc.model.export import export_facing


def classifier(crops: model.PersonCrops, held_out: model.PersonCrops, seed: int, cache: Path) -> model.FacingNet:
    """The facing classifier a compile would train from ``seed``, trained once and kept in ``cache``."""
    path = cache / f"seed{seed}.pt"
    net = model.FacingNet()
    if path.is_file():
        net.load_state_dict(torch.load(path))
        return net
    trained = model.train_facing(crops.facing, held_out.facing, seed, show_progress=False).net
    cache.mkdir(parents=True, exist_ok=True)
    torch.save(trained.state_dict(), path.with_suffix(".tmp"))
    path.with_suffix(".tmp").rename(path)
    return trained


def student(members: list[model.FacingNet], crops: np.ndarray, seed: int) -> model.FacingNet:
    """distil.py's student: trained as a compile trains its classifier, its target the members' mean probability."""
    soft = np.mean([1.0 / (1.0 + np.exp(-model._outputs(member, crops))) for member in members], axis=0)
    torch.manual_seed(seed)
    net = model.FacingNet()
    model._fit(net, crops, soft, nn.BCEWithLogitsLoss(), 1.0, seed, model.EPOCHS, False, "student")
    return net


def ship(bundle: Path, out: Path, facing_model: bytes, accuracy: float | None) -> None:
    """A copy of ``bundle`` with ``facing_model`` in place of its own, written whole or not at all."""
    partial = out.with_name(out.name + ".partial")
    if partial.exists():
        shutil.rmtree(partial)
    shutil.copytree(bundle, partial)
    manifest = json.loads((partial / "manifest.json").read_text())
    (partial / manifest["facing"]["model"]).write_bytes(facing_model)
    manifest["facing"].update(model_sha256=sha256(facing_model), held_out_accuracy=accuracy)
    (partial / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    partial.rename(out)


def main() -> None:
    renders, bundle, out = map(Path, sys.argv[1:4])
    train, held_out = model.dataset_crops(renders)
    for seed in map(int, sys.argv[4:]):
        single_out, distilled_out = out / f"single{seed}" / "bundle", out / f"distilled{seed}" / "bundle"
        if single_out.is_dir() and distilled_out.is_dir():
            continue
        start = time.perf_counter()
        members = [classifier(train, held_out, seed + offset, out / "classifiers") for offset in (0, 1000, 2000)]
        turn = model.train_face_turn(train.turn, held_out.turn, seed, show_progress=False).net
        head = model.train_head_colours(train.facing, held_out.facing, seed).net
        distilled = student(members, train.facing.crops, seed)
        report = {"seed": seed, "seconds": None}
        for name, net, path in (("single", members[0], single_out), ("distilled", distilled, distilled_out)):
            path.parent.mkdir(parents=True, exist_ok=True)
            facing_model = export_facing(net, turn, head)
            accuracy = model.accuracy(net, held_out.facing)
            ship(bundle, path, facing_model, accuracy)
            report[name] = {"held_out_accuracy": accuracy, "model_sha256": sha256(facing_model)}
        report["seconds"] = round(time.perf_counter() - start, 1)
        print(json.dumps(report), flush=True)


if __name__ == "__main__":
    main()
