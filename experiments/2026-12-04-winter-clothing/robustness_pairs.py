"""Camera life and COCO-C of each seed's two PETS09 bundles, `mixed` against `winter`, from the robustness
benchmark's reports (frozen experiment, issue 57 item 2).

    python robustness_pairs.py results/robustness > results/robustness_pairs.md

Why: a wardrobe changes what the networks learn a person looks like; the principal problem of this product is
frames that stop looking like the background. Each report is
``python -m benchmarks.robustness BUNDLE --video vtest.avi --gt gt_dev_frames_0001-0400.txt --frames 1:400:10
--background background.png --severities 1 2 3 4 5 --nudge 12 --roll 0.5 --threads 2 --unfit suppress``, copied
here as ``ARMSEED.json``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

VC = "visual compiler"
OPERATING = "visual compiler at its operating point"
EVERY = "visual compiler, every person reported"


def row(report: dict) -> list[str]:
    clean = next(c for c in report["conditions"] if c["key"] == "clean")["ap50_by_half"]
    cells = [f"{clean['choosing'][VC]:.3f} / {clean['confirming'][VC]:.3f}"]
    for family in ("camera life", "COCO-C"):
        measured = report["families"][family]
        halves = measured["by_half"]
        cells.append(f"{halves['choosing']['mPC'][VC]:.3f} / {halves['confirming']['mPC'][VC]:.3f}")
        cells.append(f"{halves['choosing']['rPC'][VC]:.3f} / {halves['confirming']['rPC'][VC]:.3f}")
        false = measured["false_people_per_frame"]
        cells.append(f"{false[OPERATING]:.2f} / {false[EVERY]:.2f}")
    return cells


def main() -> None:
    folder = Path(sys.argv[1])
    print("| bundle | clean AP50, choosing / confirming | camera life mPC | camera life rPC | camera life: false "
          "people per frame on the background, operating point / every person | COCO-C mPC | COCO-C rPC | COCO-C: "
          "false people per frame |")
    print("|---|---|---|---|---|---|---|---|")
    for seed in (0, 1, 2):
        for arm in ("mixed", "winter"):
            path = folder / f"{arm}{seed}.json"
            if path.is_file():
                print(f"| {arm}, seed {seed} | " + " | ".join(row(json.loads(path.read_text()))) + " |")


if __name__ == "__main__":
    main()
