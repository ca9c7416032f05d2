"""``vc-export``: a finished ``vc-train`` run as a bundle an appliance embeds.

    vc-export RUN -o BUNDLE [--scene SCENE.yaml] [--precision fp32|fp16|int8|auto] [--eval-samples N] [--zip]
              [--sign KEY.pem]

Writes ``BUNDLE/manifest.json`` (format version, scene and its hash, the frame camera, keypoint names and skeleton,
package versions, and per region: crop window, input size, ground polygon, owned image area, decode parameters,
precision, held-out accuracy of every precision, model and expected-height map with their SHA-256) and
``BUNDLE/models/<region>.onnx`` (uint8 crop in, heat maps out, opset 17), or one zip of the same with ``--zip``.
Each region is measured at fp32, fp16 and int8 (static quantization calibrated on its training renders) on its
held-out renders; ``auto`` keeps int8 where it holds and fp32 elsewhere. The bundle appears complete or not at
all, and is loaded back through the runtime's own validation. With ``--sign`` (an Ed25519 private key, PEM) the
manifest is signed (``manifest.sig``): ``vc-run --public-key`` and ``Runtime(..., public_key=...)`` then refuse
any bundle whose manifest was rewritten. With ``--scene`` (the scene the run was trained for; another is refused)
the bundle also carries the scene's background, reduced, as ``reference/background.npz``: the runtime measures each
frame's scene fitness against it (``vc-compile`` always gives its scene). Without it the bundle's frames' fitness is
``unknown``. Bad input prints one ``error:`` line and exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from vc import __version__
from vc.cli.common import handles_input_errors, non_negative_int, positive_int
from vc.model.precision import PRECISIONS
from vc.scenes.loader import load_scene
from vc.stages.config import ExportSettings, export_settings
from vc.stages.export import ExportResult, export


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-export", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("run", type=Path, help="a vc-train run folder")
    parser.add_argument("-o", "--output", type=Path, required=True, help="bundle folder (or .zip with --zip)")
    parser.add_argument("--scene", type=Path, metavar="SCENE.yaml",
                        help="the scene the run was trained for: the bundle then carries its background, against "
                             "which the runtime measures each frame's scene fitness (without it: unknown)")
    defaults = ExportSettings()
    parser.add_argument("--precision", choices=[*PRECISIONS, "auto"], default=defaults.precision,
                        help=f"model precision (default {defaults.precision}; auto: int8 where held-out accuracy "
                             "holds)")
    parser.add_argument("--eval-samples", type=non_negative_int, default=defaults.eval_samples,
                        help=f"held-out renders per region to measure each precision on (default "
                             f"{defaults.eval_samples}; 0: skip)")
    parser.add_argument("--calibration-samples", type=positive_int, default=defaults.calibration_samples,
                        help=f"training renders per region that calibrate int8 (default "
                             f"{defaults.calibration_samples})")
    parser.add_argument("--zip", action="store_true", help="write one zip file instead of a folder")
    parser.add_argument("--sign", type=Path, metavar="KEY.pem",
                        help="sign the manifest with this Ed25519 private key (openssl genpkey -algorithm ed25519)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    return parser


def _accuracy_table(manifest: dict) -> list[str]:
    lines = []
    for region in manifest["regions"]:
        accuracy = region["held_out_accuracy"]
        if not accuracy:
            continue
        reference = accuracy["fp32"]
        cells = []
        for precision, result in accuracy.items():
            delta = "" if precision == "fp32" else f" ({result['ap50'] - reference['ap50']:+.3f})"
            kept = "*" if precision == region["precision"] else ""
            cells.append(f"{precision}{kept} AP50 {result['ap50']:.3f}{delta} PCKh {result['pckh'] or 0:.3f}")
        lines.append(f"  {region['name']} held-out: " + ", ".join(cells))
    return lines


def report_result(result: ExportResult, output: Path) -> None:
    manifest = result.manifest
    print(f"vc-export: {len(result.bundle.regions)} region(s) of scene {manifest['scene']!r} -> {output} "
          f"({result.size_bytes / 1e6:.2f} MB, {manifest['precision']})")
    for region in manifest["regions"]:
        x0, y0, width, height = region["crop_window"]
        print(f"  {region['name']}: crop {width}x{height} at ({x0}, {y0}) -> input "
              f"{region['input_size'][0]}x{region['input_size'][1]}, {region['network']['name']} network, "
              f"{region['precision']}")
        outside = region["operators_outside_conservative_set"]
        print(f"    operators: {', '.join(region['operators'])}; "
              + (f"outside the conservative set an NPU compiler takes: {', '.join(outside)}" if outside
                 else "all in the conservative set an NPU compiler takes"))
    for line in _accuracy_table(manifest):
        print(line)
    reference = manifest.get("reference")
    if reference:
        width, height = reference["cells"]
        print(f"  scene fitness reference: {reference['made_from']}, {width}x{height} cells of "
              f"{reference['cell_px']} px")
        fit = reference.get("fit_range")
        if fit:
            print(f"  fit range (compiled for): down to {-fit['dark_stops']:+.2f} and up to "
                  f"{fit['overexposed_stops']:+.2f} stops, sharpness down to {fit['blurred_sharpness']:.2f}, "
                  f"colour cast up to {fit['colour_cast_stops']:.2f} stops, monochrome "
                  f"{'fit' if fit['monochrome'] else 'unfit'}, a veil up to {fit['veil_share']:.2f} of the light, "
                  f"noise up to {fit['noise_codes']:.1f} codes, agreement down to {fit['changed_agreement']:.2f}")
    else:
        print("  no scene fitness reference (give the run's scene with --scene): vc-run reports every frame's "
              "fitness as unknown")


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    settings = export_settings(precision=args.precision, eval_samples=args.eval_samples,
                               calibration_samples=args.calibration_samples)
    scene = load_scene(args.scene) if args.scene is not None else None
    report_result(export(args.run, args.output, settings, args.zip, args.sign, show_progress=not args.quiet,
                         scene=scene), args.output)
    return 0
