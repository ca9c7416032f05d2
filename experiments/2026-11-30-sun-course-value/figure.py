"""The held-out renders' first sample of region r0 under each sun, one above the other (frozen experiment).

    PYTHONPATH=. python experiments/2026-11-30-sun-course-value/figure.py --work DIR --out results/held_out_suns.png

``DIR`` is ``held_out_hours.py``'s ``--work``: what its samples look like under the photographed sun and the hours
the course leaves out.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from vc.io import read_image, write_image

SUNS = ("photographed", "0900", "1300", "1700")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    rows = []
    for sun in SUNS:
        image = read_image(args.work / sun / "r0" / "00000.png")
        image = cv2.resize(image, (image.shape[1] // 2, image.shape[0] // 2), interpolation=cv2.INTER_AREA)
        cv2.putText(image, sun if sun == "photographed" else f"{sun[:2]}:{sun[2:]}", (8, 22),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.7, (255, 255, 255), 2, cv2.LINE_AA)
        rows.append(image)
    write_image(args.out, np.concatenate(rows, axis=0))


if __name__ == "__main__":
    main()
