"""The control bundle with quantize.py's int8 keypoint model alone (its facing model stays fp32, as shipped; frozen).

    PYTHONPATH=src python experiments/2026-12-01-int8-crop-models/keypoint_bundle.py CONTROL INT8_BUNDLE OUT
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from vc.deploy.bundle import CROP_POSE, MANIFEST, sha256
from vc.model.export import write_bundle


def main() -> None:
    control, int8, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    manifest = json.loads((control / MANIFEST).read_text())
    files = {str(path.relative_to(control)): path.read_bytes() for path in control.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    member = manifest[CROP_POSE]["model"]
    files[member] = (int8 / member).read_bytes()
    manifest = {**manifest, CROP_POSE: {**manifest[CROP_POSE], "model_sha256": sha256(files[member])}}
    write_bundle(manifest, files, out, as_zip=False)


if __name__ == "__main__":
    main()
