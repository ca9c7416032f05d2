"""Real frames: a bundle whose networks read the person behind each peak (``second_person.py``), on
TUD-Stadtmitte's halves (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python real.py export RUN BUNDLE SCENE.yaml
    PYTHONPATH=../.. python real.py measure ARM BUNDLE -o results [--threshold T] [--halves choosing confirming]

``export``: ``vc-export RUN -o BUNDLE --scene SCENE.yaml --precision int8 --eval-samples 0`` with the behind layout
known (its channels named ``behind_score``, ``behind_offset_x``, ``behind_offset_y``). ``measure``: as
``../2026-12-01-tud-denser-crowd/measure.py`` measures one bundle (seed 0), decoded by the numpy decoder with the
people behind added at score ``T`` (none without ``--threshold``), the others as decoded without them
(``second_person.FRONT_KEPT``); writes ``results/ARM/seed0_HALF.json``, a finished file is not run again. Its control
is ``results/today/``: the compile's bundle, decoded the same way (``vc-export`` of its run gives the same models).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import second_person

import vc.deploy.bundle as bundle_module
import vc.deploy.native as native
import vc.deploy.runtime as runtime
import vc.model.export as export_module
from vc.cli import export as export_cli
from vc.deploy.heatmaps import FINE_CHANNELS, channel_names

_SPEC = importlib.util.spec_from_file_location(
    "crowd_measure", Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd" / "measure.py")
crowd_measure = sys.modules["crowd_measure"] = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(crowd_measure)


def _channel_names(channels: int) -> tuple[str, ...]:
    if channels == second_person.BEHIND_CHANNELS:
        return (*channel_names(FINE_CHANNELS), "behind_score", "behind_offset_x", "behind_offset_y")
    return channel_names(channels)


def install() -> None:
    """The behind layout known to export, bundle and runtime; the numpy decoder, the people in front kept."""
    second_person.install()
    second_person.FRONT_KEPT[0] = True
    bundle_module.LAYOUTS = second_person.decoding.LAYOUTS
    export_module.channel_names = _channel_names
    runtime.decode = second_person.decode_behind
    native.default_decoder = lambda: "numpy"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("export", "measure"))
    parser.add_argument("paths", nargs="+", help="export: RUN BUNDLE SCENE; measure: ARM BUNDLE")
    parser.add_argument("-o", "--out", type=Path)
    parser.add_argument("--threshold", type=float)
    parser.add_argument("--halves", nargs="*", default=["choosing", "confirming"])
    args = parser.parse_args()
    install()
    if args.what == "export":
        run, bundle, scene = args.paths
        sys.exit(export_cli.main([run, "-o", bundle, "--scene", scene, "--precision", "int8", "--eval-samples", "0",
                                  "--quiet"]))
    arm, bundle = args.paths
    second_person.THRESHOLD[0] = args.threshold
    sys.argv = [sys.argv[0], arm, bundle, "-o", str(args.out), "--halves", *args.halves]
    crowd_measure.main()  # one bundle: results/ARM/seed0_HALF.json

if __name__ == "__main__":
    main()
