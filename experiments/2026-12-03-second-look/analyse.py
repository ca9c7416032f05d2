"""What the dumped people say of boxes over two people (frozen experiment, issue 57 item 2): for each reported
person tall enough for the keypoint model, its width in heights and how far apart the keypoint model places the
torsos it reads at the box's left and right, beside whether the box covers a missed neighbour.

    python experiments/2026-12-03-second-look/analyse.py RESULTS/people_SEED_HALF.jsonl ...
"""

from __future__ import annotations

import json
import sys

import numpy as np

TORSO = (5, 6, 11, 12)
SURE = 0.3


def centre_x(reading: np.ndarray, points: tuple[int, ...]) -> float | None:
    sure = [reading[i, 0] for i in points if reading[i, 2] >= SURE]
    return float(np.mean(sure)) if len(sure) >= 2 else None


def matches(ious: np.ndarray, scores: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Greedy by score at IoU 0.5: the truth each detection found (-1) and whether each truth was found."""
    found = np.full(ious.shape[0], -1)
    taken = np.zeros(ious.shape[1], bool)
    for d in np.argsort(-scores):
        if not ious.shape[1]:
            break
        open_ = np.where(taken, -1.0, ious[d])
        t = int(open_.argmax())
        if open_[t] >= 0.5:
            found[d], taken[t] = t, True
    return found, taken


def rows(path: str) -> list[dict]:
    out = []
    for line in open(path):
        frame = json.loads(line)
        people = frame["people"]
        if not people:
            continue
        ious = np.array([p["ious"] for p in people]).reshape(len(people), -1)
        truth = np.array(frame["truth"]).reshape(-1, 4)
        found, taken = matches(ious, np.array([p["score"] for p in people]))
        for d, p in enumerate(people):
            box = np.array(p["box"])
            height = box[3] - box[1]
            if height < 100:
                continue
            left, right = np.array(p["left"]), np.array(p["right"])
            lx, rx = centre_x(left, TORSO), centre_x(right, TORSO)
            missed_inside = [t for t in range(len(truth)) if not taken[t] and ious[d, t] >= 0.1
                             and box[0] <= (truth[t, 0] + truth[t, 2]) / 2 <= box[2]]
            out.append({"frame": frame["frame"], "width": (box[2] - box[0]) / height, "score": p["score"],
                        "found": int(found[d]), "truth_width": (None if found[d] < 0 else
                                                                float((truth[found[d], 2] - truth[found[d], 0])
                                                                      / (truth[found[d], 3] - truth[found[d], 1]))),
                        "missed_inside": len(missed_inside),
                        "separation": None if lx is None or rx is None else (rx - lx) / height})
    return out


def main() -> None:
    people = [row for path in sys.argv[1:] for row in rows(path)]
    truth_widths = [r["truth_width"] for r in people if r["truth_width"] is not None]
    print(f"{len(people)} people >= 100 px; truth width/height of those found: median "
          f"{np.median(truth_widths):.3f}, 10-90 % {np.percentile(truth_widths, 10):.3f}-"
          f"{np.percentile(truth_widths, 90):.3f}")
    for label, chosen in (("covering a missed person", [r for r in people if r["missed_inside"]]),
                          ("found, nobody missed inside", [r for r in people if r["found"] >= 0
                                                           and not r["missed_inside"]]),
                          ("not found, nobody missed inside", [r for r in people if r["found"] < 0
                                                               and not r["missed_inside"]])):
        widths = np.array([r["width"] for r in chosen])
        seps = np.array([r["separation"] for r in chosen if r["separation"] is not None])
        print(f"{label}: {len(chosen)}; width/height quartiles {np.percentile(widths, [25, 50, 75]).round(3)}; "
              f"torso separation quartiles {np.percentile(seps, [25, 50, 75]).round(3) if len(seps) else '-'}")
    for width_floor in (0.4, 0.45, 0.5, 0.55, 0.6):
        for separation in (0.1, 0.15, 0.2, 0.25):
            split = [r for r in people if r["width"] >= width_floor and r["separation"] is not None
                     and abs(r["separation"]) >= separation]
            good = sum(1 for r in split if r["missed_inside"])
            print(f"width >= {width_floor}, separation >= {separation}: split {len(split)}, covering a missed "
                  f"person {good}, of {sum(1 for r in people if r['missed_inside'])}")


if __name__ == "__main__":
    main()
