"""A bundle whose r0 network learned a head map and a size map beside its centre map (``run.sh``), on a camera's
halves, decoded two ways (frozen experiment, issue 57 item 2).

    PYTHONPATH=../..:../../src:../2026-12-01-head-beside-centre:../2026-12-01-visible-anchor \
        python measure_heads.py CAMERA SEED BUNDLE [--all]

- ``centre_only``: the bundle as the runtime ships it (its centre map alone; the head and size maps are not read).
- ``head``: 0036's "one network" arm, as head-beside-centre's ``measure_both.py --same-head 0.1`` decodes it: r0's
  maps decoded as shipped, then from the head map (the centre at the head plus the offset there times the size
  map's height); a head-found person whose box overlaps every one of today's by less than IoU 0.5 is added, and
  dropped after the seam rule where another reported person's head lies within 0.1 of their height.

With ``--all`` (a bundle whose every region learned the head map: ``REGIONS="r0 r1" run.sh``) every region is read
so, as arms ``centre_only_all`` and ``head_all``.

Both are measured as results-as-shipped measures the shipped bundles (``vc-eval``'s scorer and miss analysis,
tracked and each frame), so the control is that experiment's ``results/CAMERA/seedS_HALF.json``. Writes
``results/CAMERA_ARM/seedS_HALF.json``; a finished file is not run again.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import threading
from pathlib import Path

import measure_both
import numpy as np
import second_look
import union
import visible_decode
from union import crowd_measure

import vc.deploy.runtime as runtime
from vc.deploy.boxes import box_iou

RESULTS = Path(__file__).parent / "results"
HALVES = ("choosing", "confirming")
SAME_HEAD = 0.1
IOU = 0.5


_ADDING = threading.Lock()  # the regions run in parallel and add to one frame's list (union._ADDED)


def every_region_people(self, frame: np.ndarray):
    """measure_both.people for every region: today's people and the head map's that no box of today's holds; the
    added are gathered over the frame's regions, and cleared once the seam rule has read them."""
    heatmaps = self.heatmaps(frame)
    today = self.faced(frame, self.people_in(heatmaps))
    with visible_decode.anchored():
        found = self.faced(frame, self.people_in(measure_both.head_maps(heatmaps)))
    boxes = np.array([person.box for person in today if not person.weak]).reshape(-1, 4)
    added = [person for person in found
             if not person.weak and (not len(boxes) or box_iou(person.box[None], boxes).max() < IOU)]
    with _ADDING:
        union._ADDED.extend(added)
    return today + added


def read_heads(every_region: bool) -> None:
    """The runtime from here on decodes r0 (or every region) as the ``head`` arm does (measure_both.py's setup, as
    union.main makes it)."""
    visible_decode.install(set(), None, 20.0, 20.0)
    second_look.IOU[0] = IOU
    runtime.RegionRunner.people = every_region_people if every_region else measure_both.people
    seam_rule = runtime.without_seam_duplicates

    def one_head_one_person(people):
        kept = union.without_added_same_heads(seam_rule(people), SAME_HEAD)
        if every_region:
            union._ADDED.clear()
        return kept

    runtime.without_seam_duplicates = one_head_one_person


def measure_arm(camera: str, arm: str, seed: int, bundle: Path) -> None:
    crowd_measure.TUD = crowd_measure.recheck.CAMERAS[camera]
    for half in HALVES:
        path = RESULTS / f"{camera}_{arm}" / f"seed{seed}_{half}.json"
        if path.exists():
            continue
        with tempfile.TemporaryDirectory() as scratch:
            result = crowd_measure.measure(bundle, crowd_measure.TUD["halves"][half], Path(scratch))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=1) + "\n")
        print(f"{camera} {arm} seed {seed} {half}: tracked {result['ap50_tracked']:.4f} each frame "
              f"{result['ap50_each_frame']:.4f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("camera", choices=sorted(crowd_measure.recheck.CAMERAS))
    parser.add_argument("seed", type=int)
    parser.add_argument("bundle", type=Path)
    parser.add_argument("--all", action="store_true", help="every region learned the head map: read them all so")
    args = parser.parse_args()
    suffix = "_all" if args.all else ""
    measure_arm(args.camera, f"centre_only{suffix}", args.seed, args.bundle)
    read_heads(args.all)
    measure_arm(args.camera, f"head{suffix}", args.seed, args.bundle)


if __name__ == "__main__":
    main()
