"""``results/summary.md``: each arm against the union as shipped (IoU 0.5: head-map-as-shipped's results), called
under 0056's band for a change read on the same bundles (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python summarise.py
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

from benchmarks.protocol import Change, difference

HERE = Path(__file__).parent
_AGAIN = importlib.util.spec_from_file_location("again_summarise",
                                                HERE.parent / "2026-12-05-head-map-again" / "summarise.py")
again = sys.modules["again_summarise"] = importlib.util.module_from_spec(_AGAIN)
_AGAIN.loader.exec_module(again)
SHIPPED = "0.5 (shipped)"
RESULTS = HERE / "results"


def main() -> None:
    arms = {SHIPPED: HERE.parent / "2026-12-05-head-map-as-shipped" / "results"}
    arms |= {folder.name: folder for folder in sorted(RESULTS.iterdir()) if folder.is_dir()}
    lines = ["# The heads' people against the centre reading's boxes (issue 57 item 2)", ""]
    for camera in again.CAMERAS:
        runs = {arm: again.runs(folder / camera) for arm, folder in arms.items()}
        lines += [f"## {again.CAMERAS[camera]}", "", f"| figure | half | {' | '.join(runs)} |",
                  "|---" * (len(runs) + 2) + "|"]
        for name in ("AP50 tracked", "AP50 each frame", "people overlapping another"):
            for half in again.HALVES:
                means = [np.mean([again.FIGURES[name](found[s, half]) for s in range(3) if (s, half) in found])
                         if any((s, half) in found for s in range(3)) else np.nan for found in runs.values()]
                lines.append(f"| {name} | {half} | {' | '.join(f'{m:.3f}' for m in means)} |")
        lines += ["", "| arm | figure | half | difference | level within | call |", "|---" * 6 + "|"]
        for arm in list(runs)[1:]:
            for name in again.CALLED:
                for half in again.HALVES:
                    seeds = [s for s in range(3) if (s, half) in runs[arm] and (s, half) in runs[SHIPPED]]
                    if not seeds:
                        continue
                    read = again.FIGURES[name]
                    called = difference(Change.READ, name, camera, half, [read(runs[SHIPPED][s, half]) for s in seeds],
                                        [read(runs[arm][s, half]) for s in seeds])
                    lines.append(f"| {arm} | {name} | {half} | {called.mean:+.3f} | ±{called.level_within:.3f} | "
                                 f"{called.call} |")
        lines.append("")
    (RESULTS / "summary.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
