"""A bundle with one bundle's region networks and another's per-person models (facing, keypoint), to tell which part
of a compile gains or loses (frozen experiment, issue 57 item 2).

    python hybrid.py BOXES PEOPLE OUT facing [crop_pose]

OUT is a copy of bundle BOXES whose listed models (``facing``, ``crop_pose``) and their manifest entries are PEOPLE's.
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path


def main() -> None:
    boxes, people, out = (Path(argument) for argument in sys.argv[1:4])
    shutil.copytree(boxes, out)
    manifest = json.loads((out / "manifest.json").read_text())
    theirs = json.loads((people / "manifest.json").read_text())
    for key in sys.argv[4:]:
        manifest[key] = theirs[key]
        shutil.copyfile(people / theirs[key]["model"], out / theirs[key]["model"])
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")


if __name__ == "__main__":
    main()
