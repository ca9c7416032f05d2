"""The people read from the heads that step 5 drops against a centre box, given to the tracker as weak people
(frozen experiment, issue 57 item 2).

    PYTHONPATH=../../src python measure.py CAMERA ARM BUNDLE --seed S      # CAMERA: pets or tud; ARM: below

On TUD-Stadtmitte's choosing half every person in a group that the bundles miss has a head reading whose head is
theirs, and 81 of 129 of those readings lie on them at IoU 0.5 or more, dropped by step 5 because their box overlaps
a centre box (often one drawn over two people) by 0.5 or more (docs/decisions/0060). Added as strong people they
bring the head map's duplicate peaks with them (0060's "replaced by them": -0.017 / -0.044). Arms:

- ``shipped``: the runtime as main has it.
- ``weak_heads``: each person read from the heads that ``with_heads_added`` drops is kept, flagged ``weak``: a
  tracker takes them only where they continue a track seen at least three times that no strong person continued
  (tracking step 1b), and drops them elsewhere; each frame on its own reports no weak person, so it is unchanged.
- ``weak_heads_apart_R``: only those whose head lies at least R of each kept strong person's height from that
  person's head (R = 0.1, 0.25).

Everything else is as shipped. Measured as ``../2026-12-04-winter-clothing/measure.py`` measures (``vc-eval``,
both halves, tracked and each frame); writes ``results/CAMERA_ARM/seedS_HALF.json``.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

import vc.deploy.decode as decode
import vc.deploy.runtime as runtime

_WINTER = importlib.util.spec_from_file_location(
    "winter_measure", Path(__file__).parent.parent / "2026-12-04-winter-clothing" / "measure.py")
winter_measure = sys.modules["winter_measure"] = importlib.util.module_from_spec(_WINTER)
_WINTER.loader.exec_module(winter_measure)

ARMS = ("shipped", "weak_heads", "weak_heads_apart_0.1", "weak_heads_apart_0.25")


def with_dropped_heads_weak(people: list, max_people: int, apart: float | None = None) -> list:
    """Step 5's union as shipped, and every strong person read from the heads that it drops, flagged weak; with
    ``apart``, only those whose head (box's top middle) lies at least ``apart`` of each kept strong person's height
    from that person's head."""
    kept = decode.with_heads_added(people, max_people)
    kept_ids = {id(person) for person in kept}
    dropped = [person for person in people if person.head_found and not person.weak and id(person) not in kept_ids]
    strong = np.array([person.box for person in kept if not person.weak], np.float64).reshape(-1, 4)
    if apart is not None and len(strong) and dropped:
        heads = np.column_stack([(strong[:, 0] + strong[:, 2]) / 2, strong[:, 1]])
        boxes = np.array([person.box for person in dropped], np.float64)
        own = np.column_stack([(boxes[:, 0] + boxes[:, 2]) / 2, boxes[:, 1]])
        distances = np.hypot(own[:, None, 0] - heads[None, :, 0], own[:, None, 1] - heads[None, :, 1])
        clear = (distances >= apart * (strong[:, 3] - strong[:, 1])[None]).all(axis=1)
        dropped = [person for person, far in zip(dropped, clear, strict=True) if far]
    for person in dropped:  # in place: the runtime knows its people by identity
        object.__setattr__(person, "weak", True)
    return kept + dropped


if __name__ == "__main__":
    arm = sys.argv[2]
    if arm not in ARMS:
        raise SystemExit(f"ARM is one of {', '.join(ARMS)}, not {arm}")
    if arm == "weak_heads":
        runtime.with_heads_added = with_dropped_heads_weak
    elif arm.startswith("weak_heads_apart_"):
        reach = float(arm.rsplit("_", 1)[1])
        runtime.with_heads_added = lambda people, max_people: with_dropped_heads_weak(people, max_people, reach)
    sys.argv += ["-o", str(Path(__file__).parent / "results")]
    winter_measure.main()
