"""The missed people in groups, summarised per half from ``hidden.py``'s and ``dump.py``'s outputs (frozen
experiment, issue 57 item 2): how hidden they are, whether a weak peak stands for them, and whether the box that
nearly matches them (IoU 0.3-0.5) is a found neighbour's or a box that found nobody (a merge, or misplaced).

    PYTHONPATH=src python experiments/2026-12-03-second-look/summarise.py RESULTS SEED > RESULTS/summary.txt
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from analyse import matches

from vc.evaluation.metrics import grouped


def hidden_summary(path: Path) -> str:
    rows = [json.loads(line) for line in path.open()]
    hidden = np.array([r["hidden"] for r in rows])
    best = np.array([r["best_iou"] for r in rows])
    weak = [r["weak_score"] for r in rows if r["weak_iou"] >= 0.5]
    return (f"{len(rows)} people in groups missed; their box hidden by nearer people's boxes: median "
            f"{np.median(hidden):.2f}, >= 0.75 {int((hidden >= 0.75).sum())}, >= 0.5 {int((hidden >= 0.5).sum())}; "
            f"a reported box at IoU 0.3-0.5 {int(((best >= 0.3) & (best < 0.5)).sum())}; a weak peak matches "
            f"{len(weak)} (scores {min(weak, default=0):.2f}-{max(weak, default=0):.2f})")


def near_miss_summary(path: Path) -> str:
    neighbours, nobody, shapes = 0, 0, []
    for line in path.open():
        frame = json.loads(line)
        people, truth = frame["people"], np.array(frame["truth"]).reshape(-1, 4)
        if not people or not len(truth):
            continue
        ious = np.array([p["ious"] for p in people])
        found, taken = matches(ious, np.array([p["score"] for p in people]))
        for t in np.flatnonzero(grouped(truth) & ~taken):
            d = int(ious[:, t].argmax())
            if not 0.3 <= ious[d, t] < 0.5:
                continue
            if found[d] >= 0:
                neighbours += 1
                continue
            nobody += 1
            box, height = np.array(people[d]["box"]), truth[t, 3] - truth[t, 1]
            shapes.append(((box[2] - box[0]) / (truth[t, 2] - truth[t, 0]), (box[3] - box[1]) / height))
    shape = (f"; those boxes' width / height against the person's, medians {np.median(shapes, axis=0).round(2)}"
             if shapes else "")
    return (f"their near misses: the box found a neighbour {neighbours}, found nobody {nobody}{shape}")


def main() -> None:
    results, seed = Path(sys.argv[1]), sys.argv[2]
    for half in ("choosing", "confirming"):
        print(f"{half}: {hidden_summary(results / f'hidden_{seed}_{half}.jsonl')}; "
              f"{near_miss_summary(results / f'people_{seed}_{half}.jsonl')}")


if __name__ == "__main__":
    main()
