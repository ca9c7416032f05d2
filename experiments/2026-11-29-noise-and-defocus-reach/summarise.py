"""The noise reach A/B (frozen experiment, issue 62): per camera, seed and half, what changed between the bundles as
shipped (``before_*``) and with their fit range's noise bound widened (``after_*``), and the change to COCO-C's mPC
and rPC (the runs hold its three noises, 15 of its 75 conditions; every other one is untouched by the change, which
acts only on frames the fitness reads too noisy); black, grey and noise frames: false people only.

    python experiments/2026-11-29-noise-and-defocus-reach/summarise.py [RESULTS]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

OURS = "visual compiler"
COCO_C_CONDITIONS = 75
RUNS = (("PETS09 choosing", "", "1"), ("PETS09 confirming", "", "201"), ("TUD-Stadtmitte first", "tud_", "1"),
        ("TUD-Stadtmitte second", "tud_", "91"))


def main() -> None:
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "results" / "ab"
    for name, prefix, half in RUNS:
        for seed in (0, 1, 2):
            paths = [root / f"{prefix}{side}_s{seed}_{half}" / "robustness.json" for side in ("before", "after")]
            if not all(path.exists() for path in paths):
                continue
            before, after = ({c["key"]: c for c in json.loads(path.read_text())["conditions"]} for path in paths)
            clean = before["clean"]["ap50"][OURS]
            assert after["clean"]["ap50"][OURS] == clean
            change, lines = 0.0, []
            for key in before:
                if key == "clean":
                    continue
                was, now = before[key].get("ap50", {}).get(OURS, 0.0), after[key].get("ap50", {}).get(OURS, 0.0)
                change += now - was
                if (was, before[key]["false_people"], before[key].get("fitness_states")) != \
                        (now, after[key]["false_people"], after[key].get("fitness_states")):
                    lines.append(f"    {key}: AP50 {was:.3f} -> {now:.3f}, false people on the background "
                                 f"{list(before[key]['false_people'].values())} -> "
                                 f"{list(after[key]['false_people'].values())} (at the operating point, reported), "
                                 f"states {before[key].get('fitness_states')} -> {after[key].get('fitness_states')}")
            print(f"{name}, seed {seed}: clean AP50 {clean:.3f}; COCO-C mPC {change / COCO_C_CONDITIONS:+.4f}, rPC "
                  f"{change / COCO_C_CONDITIONS / clean:+.4f}")
            print("\n".join(lines))


if __name__ == "__main__":
    main()
