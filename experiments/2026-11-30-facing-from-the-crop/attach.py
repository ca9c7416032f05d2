"""A compiled bundle with a facing model trained on its own compile's renders, as vc-compile now ships it (frozen,
issue 57 item 4): the control arm's bundles, unchanged, plus the model.

    PYTHONPATH=. python experiments/2026-11-30-facing-from-the-crop/attach.py BUNDLE RENDERS SEED OUT
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from vc.deploy.bundle import MANIFEST
from vc.model.export import with_facing, write_bundle
from vc.stages.train import train_facing_model


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("bundle", type=Path)
    parser.add_argument("renders", type=Path)
    parser.add_argument("seed", type=int)
    parser.add_argument("out", type=Path)
    args = parser.parse_args()
    work = args.out.with_name(args.out.name + "_facing_run")
    report = train_facing_model(args.renders, work, args.seed, show_progress=False)
    manifest = json.loads((args.bundle / MANIFEST).read_text())
    files = {str(path.relative_to(args.bundle)): path.read_bytes() for path in args.bundle.rglob("*")
             if path.is_file() and path.name != MANIFEST}
    manifest, files = with_facing(manifest, files, work)
    write_bundle(manifest, files, args.out, as_zip=False)
    print(args.out, report)


if __name__ == "__main__":
    main()
