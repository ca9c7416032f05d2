"""The people one arm misses and the control finds, on one TUD-Stadtmitte half (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python misses.py CONTROL_BUNDLE HEAD_BUNDLE HALF

The head bundle decodes as 0035's best arm (``../2026-12-01-visible-anchor/measure.py --offset-unit 20 --size-unit 20
--same-head 0.1 --size-agreement 0.15``). Prints, for each person only the head bundle misses, the frame, outcome,
whether they overlap another, their region, the best IoU of a kept detection and the near miss's box error.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "2026-12-01-visible-anchor"))
import measure as anchor_measure  # noqa: E402
import visible_decode  # noqa: E402

import vc.deploy.runtime as runtime  # noqa: E402
from vc.deploy.frames import FrameRange  # noqa: E402
from vc.deploy.tracking import TrackingConfig  # noqa: E402
from vc.evaluation.real_video import EvaluationRequest, evaluate_bundle  # noqa: E402

TUD = anchor_measure.crowd_measure.TUD


def miss_list(bundle: Path, half: str) -> dict:
    with tempfile.TemporaryDirectory() as scratch:
        request = EvaluationRequest(bundle=bundle, video=TUD["video"], ground_truth=TUD["gt"], output=Path(scratch),
                                    frames=FrameRange.parse(TUD["halves"][half]), hog=False, threads=2,
                                    tracking=TrackingConfig(), fps=TUD["fps"])
        misses = evaluate_bundle(request, show_progress=False).misses
    return {(person.frame, tuple(person.box.round(1))): person for person in misses.people if person.outcome != "found"}


def main() -> None:
    control, head, half = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    missed_by_control = miss_list(control, half)
    seam_rule = runtime.without_seam_duplicates
    runtime.without_seam_duplicates = lambda people: anchor_measure.without_same_heads(seam_rule(people), 0.1)
    visible_decode.install({(32, 96)}, None, 20.0, 20.0, True, 0.15)
    missed_by_head = miss_list(head, half)
    only = sorted(key for key in missed_by_head if key not in missed_by_control)
    print(f"{half}: the control misses {len(missed_by_control)}, the head bundle {len(missed_by_head)}, "
          f"{len(only)} of them only it")
    for key in only:
        person = missed_by_head[key]
        error = person.box_error() or {}
        print(f"  frame {person.frame}: {person.outcome}, {'overlapping' if person.grouped else 'apart'}, "
              f"{person.region}, best IoU {person.best_iou:.2f}, "
              + ", ".join(f"{name} {value:.2f}" for name, value in error.items()))


if __name__ == "__main__":
    main()
