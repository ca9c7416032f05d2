"""``vc-export``: a finished ``vc-train`` run as a bundle an appliance embeds.

    vc-export RUN -o BUNDLE [--zip]

Writes ``BUNDLE/manifest.json`` (format version, scene and its hash, the frame camera, keypoint names and skeleton,
package versions, and per region: crop window, input size, ground polygon, owned image area, decode parameters,
model and expected-height map with their SHA-256) and ``BUNDLE/models/<region>.onnx`` (uint8 crop in, heat maps
out, opset 17), or one zip of the same with ``--zip``. The bundle appears complete or not at all. It is then
loaded back through the runtime's own validation. Bad input prints one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors
from vc.deploy.bundle import load_bundle
from vc.model.export import bundle_files, write_bundle


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-export", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("run", type=Path, help="a vc-train run folder")
    parser.add_argument("-o", "--output", type=Path, required=True, help="bundle folder (or .zip with --zip)")
    parser.add_argument("--zip", action="store_true", help="write one zip file instead of a folder")
    return parser


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    manifest, files = bundle_files(args.run)
    write_bundle(manifest, files, args.output, args.zip)
    bundle = load_bundle(args.output)
    size = sum(len(data) for data in files.values())
    print(f"vc-export: {len(bundle.regions)} region(s) of scene {manifest['scene']!r} -> {args.output} "
          f"({size / 1e6:.2f} MB)")
    for region in manifest["regions"]:
        x0, y0, width, height = region["crop_window"]
        print(f"  {region['name']}: crop {width}x{height} at ({x0}, {y0}) -> input "
              f"{region['input_size'][0]}x{region['input_size'][1]}, {region['network']['name']} network")
    return 0
