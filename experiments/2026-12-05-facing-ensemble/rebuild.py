"""A compile's facing model trained again as the product now trains it, the mean of ``MEMBERS`` networks in one
graph (:func:`vc.stages.train.train_facing_model`), shipped in a copy of the compile's bundle in place of its own
(frozen experiment, issue 57 item 4): the bundles as a compile now makes them.

    PYTHONPATH=../../src python rebuild.py RENDERS BUNDLE OUT --seed S

The run (``OUT_run``) keeps what the facing model measured (``facing.json``). Only the facing model differs from
BUNDLE's: a compile of the same scene and seed renders the same shards and trains the same region networks.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from vc.deploy.bundle import sha256
from vc.stages.train import train_facing_model


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("renders", type=Path)
    parser.add_argument("bundle", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    args = parser.parse_args()
    run = args.out.parent / f"{args.out.name}_run"
    run.mkdir(parents=True, exist_ok=True)
    measured = train_facing_model(args.renders, run, args.seed, show_progress=False)
    if args.out.exists():
        shutil.rmtree(args.out)
    shutil.copytree(args.bundle, args.out)
    manifest = json.loads((args.out / "manifest.json").read_text())
    model = (run / "facing.onnx").read_bytes()
    (args.out / manifest["facing"]["model"]).write_bytes(model)
    manifest["facing"].update(model_sha256=sha256(model), held_out_accuracy=measured["held_out_accuracy"],
                              face_turn_held_out_error=measured["face_turn"].get("held_out_error"),
                              head_held_out_auc=measured["head_colours"]["held_out_auc"])
    (args.out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    print(f"{args.out}: held-out accuracy {measured['held_out_accuracy']}, {measured['seconds']} s", flush=True)


if __name__ == "__main__":
    main()
