"""Does following the sun's course buy accuracy at hours it never rendered? (issue 62; frozen experiment)

    PYTHONPATH=. python experiments/2026-11-30-sun-course-value/held_out_hours.py \
        --bundle course=RUN_A/bundle --bundle photographed=RUN_B/bundle --samples 120 --work DIR --out results

Renders the dated demo (``examples/scenes/demo_dated/scene.yaml``) under the sun of hours its course leaves out
(09:00 to 17:00, odd hours) and under the photographed sun, ``--samples`` held-out samples per region and hour (seed 7,
which no compile used), and measures each bundle's region models on them: AP50 through the deployment decoder
(:func:`vc.model.precision.evaluate_model`, as the export measures a precision). Writes ``held_out_hours.json`` and
``held_out_hours.md`` to ``--out``.

One sample of every region is rendered under one sun: the synthesizer's photographed light is replaced by the hour's
(the course's own draw picks among positions at random, and a measurement per hour needs each sample at that hour).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from datetime import datetime
from pathlib import Path

import numpy as np

from vc.calibration.lighting import solar_position
from vc.deploy.bundle import load_bundle
from vc.io import write_image, write_json
from vc.model.precision import evaluate_model
from vc.render.bodies import BodyModel
from vc.render.dataset import Sample
from vc.render.plan import plan_render
from vc.render.sun_course import SunPosition
from vc.render.synthesis import RegionSynthesizer, SynthesisSettings
from vc.scenes.loader import load_scene
from vc.scenes.regions import plan_regions

SCENE = Path("examples/scenes/demo_dated/scene.yaml")
HOURS = (9, 11, 13, 15, 17)
#: A seed no compile of the experiment used: held-out people, poses and clothes.
SEED = 7


def hour_position(lighting, hour: int) -> SunPosition:
    moment = datetime.combine(lighting.time.date(), datetime.min.time().replace(hour=hour), tzinfo=lighting.time.tzinfo)
    azimuth, elevation = solar_position(*lighting.location, moment, lighting.north_deg)
    return SunPosition(moment.isoformat(), azimuth, elevation)


def render_hour(scene, region, plan, bodies, position: SunPosition | None, samples: int, folder: Path) -> list[Sample]:
    """``samples`` samples of ``region`` under ``position`` (None: the photographed sun), written to ``folder``."""
    if position is None:
        course = [plan.sun_course[0]]
    else:
        course = [plan.sun_course[0], position]
    effects = [replace(decision, parameters={"positions": [p.to_dict() for p in course]})
               if decision.name == "sun_course" else decision for decision in plan.effects]
    synthesizer = RegionSynthesizer(scene, region, bodies, SynthesisSettings(seed=SEED), replace(plan, effects=effects))
    if position is not None:
        synthesizer._lights[0] = synthesizer.light(1)  # every sample under the hour's sun (module docstring)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for index in range(samples):
        sample = synthesizer.sample(index)
        image_path, mask_path = folder / f"{index:05d}.png", folder / f"{index:05d}.mask.png"
        write_image(image_path, sample.image)
        write_image(mask_path, np.repeat(sample.instances[..., None], 3, axis=-1))
        written.append(Sample(image_path, mask_path, sample.annotations))
    return written


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bundle", action="append", required=True, metavar="NAME=PATH")
    parser.add_argument("--samples", type=int, default=120)
    parser.add_argument("--work", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    bundles = {name: load_bundle(path) for name, path in (spec.split("=", 1) for spec in args.bundle)}
    names = list(bundles)

    scene = load_scene(SCENE)
    regions = plan_regions(scene)
    plan = plan_render(scene, regions, time_costs=False)
    bodies = BodyModel()
    suns = {"photographed": None} | {f"{hour:02d}:00": hour_position(scene.lighting, hour) for hour in HOURS}
    rows = []
    for label, position in suns.items():
        for region in regions:
            samples = render_hour(scene, region, plan, bodies, position, args.samples,
                                  args.work / label.replace(":", "") / region.name)
            row = {"sun": label, "region": region.name, "samples": len(samples),
                   "people": sum(len(sample.annotations) for sample in samples)}
            if position is not None:
                row.update(azimuth_deg=round(position.azimuth_deg, 1), elevation_deg=round(position.elevation_deg, 1))
            for name, bundle in bundles.items():
                entry = next(entry for entry in bundle.regions if entry.name == region.name)
                evaluation = evaluate_model(entry.model, samples, entry.crop_window[2:], entry.decode,
                                            entry.expected_height_px).evaluation
                row[name] = round(float(evaluation.ap50), 4)
            print(json.dumps(row), flush=True)
            rows.append(row)

    means = {name: {label: round(float(np.mean([r[name] for r in rows if r["sun"] == label])), 4) for label in suns}
             for name in names}
    held_out = {name: round(float(np.mean([r[name] for r in rows if r["sun"] != "photographed"])), 4)
                for name in names}
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "held_out_hours.json", {"scene": str(SCENE), "seed": SEED, "samples": args.samples,
                                                  "bundles": names,
                                                  "rows": rows, "mean_by_sun": means, "mean_held_out_hours": held_out})
    lines = ["| sun | " + " | ".join(f"AP50 {name}" for name in names) + " |", "|---|" + "---|" * len(names)]
    lines += [f"| {label} | " + " | ".join(f"{means[name][label]:.3f}" for name in names) + " |" for label in suns]
    lines += ["| **held-out hours** | " + " | ".join(f"**{held_out[name]:.3f}**" for name in names) + " |"]
    (args.out / "held_out_hours.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
