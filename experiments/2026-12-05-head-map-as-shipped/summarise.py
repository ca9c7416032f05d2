"""``results/summary.md``: the head-map compiles against the shipped ones, seed by seed, called under 0056's band,
with pose agreement and the time a frame (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python summarise.py

``head`` (as shipped with the head map) and ``centre_only`` (the same bundles without step 5) are retrained changes
against results-as-shipped's ``shipped``; ``head`` against ``centre_only`` is the same networks read another way.
Pose and time: ``results/pose_CAMERA.jsonl`` (keypoint-model-capacity's ``measure.py``, the shipped and the head
bundle read in turn in one process, so their time is a ratio measured in one run).
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

from benchmarks.protocol import Change, difference

HERE = Path(__file__).parent
_AGAIN = importlib.util.spec_from_file_location("again_summarise",
                                                HERE.parent / "2026-12-05-head-map-again" / "summarise.py")
again = sys.modules["again_summarise"] = importlib.util.module_from_spec(_AGAIN)
_AGAIN.loader.exec_module(again)
RESULTS = HERE / "results"
ARMS = {"shipped": again.SHIPPED, "centre_only": RESULTS / "centre_only", "head": RESULTS}
COMPARISONS = (("head", "shipped", Change.RETRAINED), ("centre_only", "shipped", Change.RETRAINED),
               ("head", "centre_only", Change.READ))
POSE = ("each frame", "tracked")


def pose_lines(camera: str) -> list[str]:
    path = RESULTS / f"pose_{camera}.jsonl"
    if not path.exists():
        return []
    lines = [json.loads(line) for line in path.read_text().splitlines()]
    rows = ["| pose agreement / time | half | shipped | head | seeds (shipped / head) | difference | level within "
            "| call |", "|---" * 8 + "|"]
    for index, half in enumerate(again.HALVES):
        chosen = [line for line in lines if (line["frames"][0] == 1) == (index == 0)]
        for reading in POSE:
            shipped = [line["readings"][f"shipped, {reading}"]["overall"] for line in chosen]
            head = [line["readings"][f"head, {reading}"]["overall"] for line in chosen]
            called = difference(Change.RETRAINED, f"pose {reading}", camera, half, shipped, head)
            rows.append(f"| pose {reading} | {half} | {np.mean(shipped):.3f} | {np.mean(head):.3f} | "
                        f"{', '.join(f'{v:.3f}' for v in shipped)} / {', '.join(f'{v:.3f}' for v in head)} | "
                        f"{called.mean:+.3f} | ±{called.level_within:.3f} | {called.call} |")
        ratios = [line["time_ratio"]["head"] for line in chosen]
        rows.append(f"| time a frame, head / shipped | {half} | 1 | {np.mean(ratios):.2f} | "
                    f"{', '.join(f'{v:.2f}' for v in ratios)} | | | |")
    return rows + [""]


def camera_lines(camera: str) -> list[str]:
    arms = {arm: again.runs(folder / camera) for arm, folder in ARMS.items()}
    seeds = sorted({seed for seed, _ in arms["head"]})
    if not seeds:
        return []
    lines = [f"## {again.CAMERAS[camera]}: seeds {', '.join(map(str, seeds))}", "",
             f"| figure | half | {' | '.join(arms)} | seeds ({' / '.join(arms)}) |", "|---" * (len(arms) + 3) + "|"]
    for name, read in again.FIGURES.items():
        for half in again.HALVES:
            values = {arm: [read(found[seed, half]) for seed in seeds if (seed, half) in found]
                      for arm, found in arms.items()}
            means = " | ".join(f"{np.mean(v):.3f}" if v else "–" for v in values.values())
            each = " / ".join(", ".join(f"{x:.3f}" for x in v) for v in values.values())
            lines.append(f"| {name} | {half} | {means} | {each} |")
    lines += ["", "| change | against | figure | half | difference | level within | call |", "|---" * 7 + "|"]
    for arm, against, change in COMPARISONS:
        for name in again.CALLED:
            for half in again.HALVES:
                both = [seed for seed in seeds if (seed, half) in arms[arm] and (seed, half) in arms[against]]
                if not both:
                    continue
                read = again.FIGURES[name]
                called = difference(change, name, camera, half, [read(arms[against][s, half]) for s in both],
                                    [read(arms[arm][s, half]) for s in both])
                lines.append(f"| {arm} | {against} | {name} | {half} | {called.mean:+.3f} | "
                             f"±{called.level_within:.3f} | {called.call} |")
    return lines + [""] + pose_lines(camera)


def main() -> None:
    lines = ["# The head map compiled as the scenes ship (issue 57 item 2)", ""]
    for camera in again.CAMERAS:
        lines += camera_lines(camera)
    (RESULTS / "summary.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
