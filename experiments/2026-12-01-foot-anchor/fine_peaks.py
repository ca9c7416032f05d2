"""Probe: today's bundles decoded from their fine centre map's peaks instead of the coarse map's, on both halves of
TUD-Stadtmitte (frozen). The fine map (twice the resolution) gives 0.76 of the held-out r0 people overlapping another
a peak of their own against the coarse map's 0.63 (``foot_anchor.py peaks --fine``); decision 0010 read the fine
peaks on all frames, before the denser crowd, and kept the coarse ones.

    PYTHONPATH=../.. python fine_peaks.py ARM B0 B1 B2 -o results      # ARM: coarse or fine

The numpy decoder, as it is, with ``find_peaks`` of step 1 reading the fine map (its peaks brought back to cells);
everything after step 1 unchanged. Writes ``results/ARM/seedS_HALF.json`` as ``../2026-12-01-tud-denser-crowd/
measure.py`` does.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
from pathlib import Path

import vc.deploy.decode as decoding
import vc.deploy.native as native
import vc.deploy.runtime as runtime
from vc.deploy.heatmaps import FINE_CENTRE_CHANNELS, FINE_CHANNELS, FINE_FACTOR, fine_centre_map, input_to_cells

_MEASURE = importlib.util.spec_from_file_location(
    "measure", Path(__file__).parent.parent / "2026-12-01-tud-denser-crowd" / "measure.py")
measure = sys.modules["measure"] = importlib.util.module_from_spec(_MEASURE)
_MEASURE.loader.exec_module(measure)


def _fine_peak_decode(heatmaps, config, expected_height_px=None, weak_above=None, prior=decoding.UPRIGHT_PRIOR):
    if heatmaps.shape[0] != FINE_CHANNELS:
        return decoding.decode(heatmaps, config, expected_height_px, weak_above, prior)
    fine = fine_centre_map(heatmaps[FINE_CENTRE_CHANNELS])
    coarse_peaks = decoding.find_peaks

    def fine_peaks(_coarse, threshold, limit=None):
        return [(value, input_to_cells(position, FINE_FACTOR))
                for value, position in coarse_peaks(fine, threshold, limit)]

    decoding.find_peaks = fine_peaks
    try:
        return decoding.decode(heatmaps, config, expected_height_px, weak_above, prior)
    finally:
        decoding.find_peaks = coarse_peaks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("arm", choices=("coarse", "fine"))
    parser.add_argument("bundles", type=Path, nargs="+")
    parser.add_argument("-o", "--out", type=Path, required=True)
    args = parser.parse_args()
    native.default_decoder = lambda: "numpy"
    if args.arm == "fine":
        runtime.decode = _fine_peak_decode
    for half in ("choosing", "confirming"):
        for seed, bundle in enumerate(args.bundles):
            path = args.out / args.arm / f"seed{seed}_{half}.json"
            if path.exists():
                continue
            with tempfile.TemporaryDirectory() as scratch:
                result = measure.measure(bundle, measure.TUD["halves"][half], Path(scratch))
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(result, indent=1) + "\n")
            print(args.arm, seed, half, result["ap50_tracked"], result["ap50_each_frame"], flush=True)


if __name__ == "__main__":
    main()
