"""A winter bundle's facing model trained again on renders of the same scene and seed whose winter hats include
light knits, shipped in a copy of the bundle in place of its own (frozen experiment, issue 57 item 4).

    PYTHONPATH=../../src python facing_knits.py SCENE BUNDLE RENDERS OUT --seed S \
        --report results/facing_CAMERA_seedS.json

Why: described in winter coats ([0053](../../docs/decisions/0053-scenes-in-the-clothes-their-people-wear.md)),
TUD-Stadtmitte's compiles read a man in black with a light head, seen from behind, as facing the camera, and their
pose falls 0.04-0.05 each frame. The winter wardrobe's hats and hoods are all dark, so its renders hold fewer light
heads than the default wardrobe's (12 % against 18 % of people); real winter knits are often cream, white or light
grey. Does a facing model that has seen light hats from behind read him, and the rest, as the default one did?

The renders are the compile's render stage (``vc-render`` with the compile's samples, spp and seed) with
:data:`LIGHT_KNITS` added to the winter hats; the facing model is trained on them as a compile trains it
(:func:`vc.stages.train.train_facing_model`). Only the facing model differs from BUNDLE's.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import shutil
from pathlib import Path

from vc.cli import render as render_cli
from vc.deploy.bundle import sha256
from vc.render import appearance
from vc.stages.train import train_facing_model

#: The winter hats and hoods with light knits among them (sRGB: cream, light grey, beige), so that about as many
#: winter people show a light head as in the default wardrobe; the dark colours keep their proportions.
LIGHT_KNITS = {"#151515": 42, "#333335": 17, "#1f2a44": 13, "#6f6f6f": 8, "#9b1b1b": 4,
               "#e6e2d8": 8, "#bdbab3": 5, "#b39b72": 3}


def dress_winter_in_light_knits() -> None:
    """Replace the winter wardrobe's headwear colours in this process (the render stage reads ``WARDROBES``)."""
    winter = appearance.WARDROBES["winter"]
    appearance.WARDROBES["winter"] = dataclasses.replace(winter, headwear_colours=appearance._palette(LIGHT_KNITS))


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
    dress_winter_in_light_knits()
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
    report = {"scene": str(args.scene), "seed": args.seed, "light_knits": LIGHT_KNITS,
              **{key: value for key, value in measured.items() if key != "trained_on"}}
    args.report.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
