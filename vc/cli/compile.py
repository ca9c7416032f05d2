"""``vc-compile``: a scene description in, a tested ONNX bundle out — every stage in one command.

    vc-compile SCENE -o OUT [--budget quick|standard|full] [--seed K] [--quiet]

Stages: check (validate the scene, plan its regions) -> render (``OUT/renders``) -> train (``OUT/run``) -> export
(``OUT/bundle``, precision ``auto``: int8 where it holds on held-out renders) -> self-test (the bundle through the
runtime on full frames composed of held-out renders on the scene's background: AP50, ms/frame, false alarms on
the empty background; ``OUT/overlay.png``). ``OUT/compile.json`` records each finished stage; running the same
command again skips those and resumes the interrupted one where it stopped (render shards and training
checkpoints are kept). Prints one summary at the end: time per stage, held-out synthetic accuracy, bundle size,
runtime ms/frame. Bad input exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

from vc import __version__
from vc.cli import export as export_cli
from vc.cli import render as render_cli
from vc.cli import train as train_cli
from vc.cli.common import handles_input_errors
from vc.errors import InputError
from vc.io import read_image, write_image, write_json

STATE = "compile.json"


@dataclass(frozen=True)
class Budget:
    """How much work a compile spends: the knobs that trade compile time for accuracy."""

    samples: int  # rendered samples per region
    spp: int  # path-tracing samples per pixel
    steps: int  # training steps per region (batches of 16 windows)
    eval_samples: int  # held-out renders each export precision is measured on
    selftest_frames: int


BUDGETS = {
    # about 10 minutes for the demo scene on 2 cores: a working bundle, not an accurate one
    "quick": Budget(samples=300, spp=16, steps=200, eval_samples=100, selftest_frames=8),
    # the default: about 20 minutes of training per region on 2 cores
    "standard": Budget(samples=2000, spp=16, steps=1800, eval_samples=200, selftest_frames=50),
    "full": Budget(samples=6000, spp=32, steps=5000, eval_samples=200, selftest_frames=100),
}
SHARD_SIZE = 100


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-compile", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("scene", type=Path, help="scene YAML")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    parser.add_argument("--budget", choices=list(BUDGETS), default="standard",
                        help="quick (~10 min, demo quality), standard (default) or full")
    parser.add_argument("--seed", type=int, default=0, help="seed of the renders and the training")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


class _Compile:
    """The stages and their record in ``OUT/compile.json``."""

    def __init__(self, args: argparse.Namespace) -> None:
        from vc.scenes.loader import load_scene

        self.args, self.out = args, args.output
        self.scene = load_scene(args.scene)
        self.budget = BUDGETS[args.budget]
        self.settings = {"scene": str(args.scene), "scene_hash": self.scene.content_hash, "budget": args.budget,
                         **asdict(self.budget), "seed": args.seed}
        self.state = self._read_state()

    def _read_state(self) -> dict:
        path = self.out / STATE
        if path.is_file():
            try:
                state = json.loads(path.read_text())
            except json.JSONDecodeError as error:
                raise InputError(path, "", f"not valid JSON ({error}); delete it to start over") from None
            if state.get("settings") == self.settings:
                return state
            print(f"vc-compile: settings differ from {path}'s; every stage runs again (kept work is reused "
                  "where it still fits)")
        return {"settings": self.settings, "stages": {}}

    def run(self, name: str, stage: Callable[[], dict]) -> dict:
        record = self.state["stages"].get(name)
        if record:
            print(f"== {name}: done before ({record['seconds']:.0f} s), skipped")
            return record
        print(f"== {name}")
        start = time.perf_counter()
        result = stage()
        record = {"seconds": round(time.perf_counter() - start, 1), **result}
        self.state["stages"][name] = record
        write_json(self.out / STATE, self.state)
        return record

    def _quiet(self) -> list[str]:
        return ["--quiet"] if self.args.quiet else []

    def check(self) -> dict:
        from vc.scenes.regions import plan_regions

        regions = plan_regions(self.scene)
        return {"regions": [{"name": r.name, "input_size": list(r.input_size)} for r in regions]}

    def render(self) -> dict:
        code = render_cli.main([str(self.args.scene), "-o", str(self.out / "renders"), "--samples",
                                str(self.budget.samples), "--spp", str(self.budget.spp), "--seed",
                                str(self.args.seed), "--shard-size", str(SHARD_SIZE), *self._quiet()])
        _succeeded(code)
        return {}

    def train(self) -> dict:
        code = train_cli.main([str(self.out / "renders"), "-o", str(self.out / "run"), "--all", "--steps",
                               str(self.budget.steps), "--seed", str(self.args.seed), *self._quiet()])
        _succeeded(code)
        metrics = json.loads((self.out / "run" / train_cli.METRICS).read_text())
        return {"held_out": {name: {key: region[key] for key in ("ap50", "pckh", "mask_iou")}
                             for name, region in metrics["regions"].items()}}

    def export(self) -> dict:
        code = export_cli.main([str(self.out / "run"), "-o", str(self.out / "bundle"), "--precision", "auto",
                                "--eval-samples", str(self.budget.eval_samples), *self._quiet()])
        _succeeded(code)
        manifest = json.loads((self.out / "bundle" / "manifest.json").read_text())
        size = sum(path.stat().st_size for path in (self.out / "bundle").rglob("*") if path.is_file())
        return {"bundle_bytes": size, "precision": {r["name"]: r["precision"] for r in manifest["regions"]}}

    def self_test(self) -> dict:
        from vc.deploy.runtime import Runtime
        from vc.model.data import open_region
        from vc.render.dataset import read_manifest
        from vc.selftest import self_test

        renders = self.out / "renders"
        regions = [open_region(renders, name) for name in read_manifest(renders)["regions"]]
        with Runtime(self.out / "bundle") as runtime:
            result = self_test(runtime, read_image(self.scene.image_path), regions, self.budget.selftest_frames)
        write_image(self.out / "overlay.png", result.overlay)
        return result.to_dict()


class StageFailed(Exception):
    """A stage's command failed; it has printed its own error. Carries its exit status."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


def _succeeded(code: int) -> None:
    if code != 0:
        raise StageFailed(code)


def _summary(state: dict, out: Path) -> str:
    stages = state["stages"]
    lines = ["", "vc-compile summary",
             "  stage       seconds (of the run that did the stage; a resumed stage counts from its resume)"]
    lines += [f"  {name:<10} {record['seconds']:8.0f}" for name, record in stages.items()]
    lines.append(f"  total      {sum(record['seconds'] for record in stages.values()):8.0f}")
    for name, accuracy in stages["train"]["held_out"].items():
        lines.append(f"  {name}: held-out synthetic AP50 {accuracy['ap50']:.3f}, PCKh@0.5 {accuracy['pckh'] or 0:.3f}, "
                     f"mask IoU {accuracy['mask_iou'] or 0:.3f}, {stages['export']['precision'][name]}")
    test = stages["self-test"]
    lines.append(f"  bundle {stages['export']['bundle_bytes'] / 1e6:.2f} MB -> {out / 'bundle'}")
    lines.append(f"  self-test on {test['frames']} composed full frames: AP50 {test['ap50']:.3f}, "
                 f"{test['ms_per_frame']:.1f} ms/frame, {test['false_alarms_on_background']} false alarm(s) on the "
                 f"empty background -> {out / 'overlay.png'}")
    return "\n".join(lines)


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    job = _Compile(args)
    try:
        job.run("check", job.check)
        job.run("render", job.render)
        job.run("train", job.train)
        job.run("export", job.export)
        job.run("self-test", job.self_test)
    except StageFailed as failure:
        return failure.code
    print(_summary(job.state, args.output))
    return 0
