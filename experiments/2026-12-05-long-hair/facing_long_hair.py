"""A bundle's facing model trained again on renders of the same scene and seed whose people's hair is long as often
as on a street, shipped in a copy of the bundle in place of its own (frozen experiment, issue 57 item 4).

    PYTHONPATH=../../src python facing_long_hair.py SCENE BUNDLE RENDERS OUT --seed S \
        --report results/facing_CAMERA_seedS.json

Why (``../2026-12-05-which-pairs-swap``): on TUD-Stadtmitte the facing model is surely wrong, over many frames and
on every seed, about women with long hair: seen from behind (hair over the nape and the back, no neck to see) it
reads a face; seen from the front (hair beside the face) a back. The renders' hair covers the scalp only.

The renders are the compile's render stage (``vc-render`` with the compile's samples, spp and seed) with
:data:`LONG_HAIR`; the facing model is trained on them as a compile trains it
(:func:`vc.stages.train.train_facing_model`). Only the facing model differs from BUNDLE's.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from vc.cli import render as render_cli
from vc.deploy.bundle import sha256
from vc.render import appearance
from vc.stages.train import train_facing_model

#: Set before measuring, this project's assumption from street observation: of women, a quarter with hair to the
#: shoulders and nearly half with hair past them; of men, one in ten with either.
LONG_HAIR = appearance.HairLengths(to_shoulders=(0.25, 0.07), past_shoulders=(0.45, 0.03))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("bundle", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--samples", type=int, default=2000)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--report", type=Path, required=True, help="what the facing model measured (JSON)")
    args = parser.parse_args()
    appearance.HAIR_LENGTHS = LONG_HAIR
    render_cli.main([str(args.scene), "-o", str(args.renders), "--samples", str(args.samples), "--spp",
                     str(args.spp), "--seed", str(args.seed), "--quiet"])
    run = args.renders.parent / f"{args.renders.name}_run"
    run.mkdir(exist_ok=True)
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
    report = {"scene": str(args.scene), "seed": args.seed,
              "long_hair": {"to_shoulders": LONG_HAIR.to_shoulders, "past_shoulders": LONG_HAIR.past_shoulders},
              **{key: value for key, value in measured.items() if key != "trained_on"}}
    args.report.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
