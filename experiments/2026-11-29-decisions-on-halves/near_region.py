"""Decision 0009 re-checked on the halves: PETS09's near region r2 planned at 36 px (today) against 48 px, the
size it had before 0009 (frozen experiment, issue 57: near people are what the kept frames miss).

    python experiments/2026-11-29-decisions-on-halves/near_region.py COMPILE_OUT WORK

``COMPILE_OUT`` is a standard compile of ``examples/scenes/pets09_s2l1/scene.yaml`` (its ``compile_config.yaml``
and ``bundle/``). Its r2 is rendered again at 48 px with the compile's render settings and seed, trained with its
training settings, and exported as the compile exports; ``WORK/bundle`` is the compile's bundle with r2 (model,
expected heights, manifest entry) taken from that export. Regions are rendered and trained independently and r2's
crop window and ground polygon do not depend on the planned size, so this is what a compile of the scene with r2 at
48 px makes, up to the scene hash that enters each sample's random generator. Resumable: each stage resumes its
own work.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
from pathlib import Path

import yaml

from vc.scenes.loader import load_scene
from vc.stages.config import read_config
from vc.stages.export import export
from vc.stages.render import render
from vc.stages.train import train

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "pets09_s2l1" / "scene.yaml"
REGION, PERSON_PX = "r2", 48


def variant_scene(work: Path) -> Path:
    """The PETS09 scene with r2 planned at 48 px, its files named by absolute paths."""
    data = yaml.safe_load(SCENE.read_text())
    for key in ("image", "video"):
        data[key] = str((SCENE.parent / data[key]).resolve())
    data["regions"]["person_px_by_region"][REGION] = PERSON_PX
    path = work / "scene.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def assemble(bundle: Path, replacement: Path, output: Path) -> None:
    """``bundle`` with its r2 taken from ``replacement`` (files hard-linked; the manifest written anew)."""
    if output.exists():
        shutil.rmtree(output)
    shutil.copytree(bundle, output, copy_function=os.link)
    manifest = json.loads((output / "manifest.json").read_text())
    theirs = next(entry for entry in json.loads((replacement / "manifest.json").read_text())["regions"]
                  if entry["name"] == REGION)
    for index, entry in enumerate(manifest["regions"]):
        if entry["name"] == REGION:
            manifest["regions"][index] = theirs
    for key in ("model", "expected_height"):
        (output / theirs[key]).unlink()
        os.link(replacement / theirs[key], output / theirs[key])
    (output / "manifest.json").unlink()
    (output / "manifest.json").write_text(json.dumps(manifest, indent=1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("compiled", type=Path)
    parser.add_argument("work", type=Path)
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    config = read_config(args.compiled / "compile_config.yaml")
    scene = variant_scene(args.work)
    render(scene, args.work / "renders", config.render, [REGION], show_progress=False)
    train(args.work / "renders", args.work / "run", config.train, [REGION], show_progress=False)
    if not (args.work / "bundle_r2" / "manifest.json").exists():
        export(args.work / "run", args.work / "bundle_r2", config.export, show_progress=False,
               scene=load_scene(scene))
    assemble(args.compiled / "bundle", args.work / "bundle_r2", args.work / "bundle")
    print(f"{args.work / 'bundle'}: {args.compiled / 'bundle'} with r2 at {PERSON_PX} px")


if __name__ == "__main__":
    main()
