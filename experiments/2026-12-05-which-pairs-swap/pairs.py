"""Which of a person's left/right pairs the bundle reads the other way round from YOLO11n-pose @1280, and of whom
(frozen experiment, issue 57 item 4). Reads ``collect.py``'s files.

    PYTHONPATH=../../src python pairs.py FILE.pkl ...

A pair counts where the reference is sure of both members and they stand at least the agreement distance apart
(closer, their order cannot change agreement). It is the other way round where its two members agree with the
reference's exchanged and not as they are.
"""

from __future__ import annotations

import collections
import pickle
import sys

import numpy as np

from vc.deploy.heatmaps import PAIRS
from vc.evaluation.agreement import AGREEMENT_HEAD_SIZES, HEAD_FRACTION_OF_HEIGHT, REFERENCE_CONFIDENCE, matched_people
from vc.evaluation.metrics import ImageResult
from vc.keypoints import COCO_KEYPOINTS

PAIR_NAMES = [COCO_KEYPOINTS[left].removeprefix("left_") for left, _ in PAIRS]
LIMBS = {"head": {"eye", "ear"}, "arms": {"shoulder", "elbow", "wrist"}, "legs": {"hip", "knee", "ankle"}}


def _image(truth, people) -> ImageResult:
    return ImageResult(truth_boxes=truth, boxes=np.array([p["box"] for p in people]).reshape(-1, 4),
                       scores=np.array([p["score"] for p in people]),
                       keypoints=np.array([p["keypoints"] for p in people]).reshape(-1, 17, 3))


def pair_states(frames: list[dict], which: str = "ours"):
    """Per matched person: {pair name: True (other way round) / False (as the reference)}, and facts of them."""
    ours = [_image(f["truth"], f[which]) for f in frames]
    theirs = [ImageResult(truth_boxes=f["truth"], **f["theirs"]) for f in frames]
    for frame, mine, ref, our_matches, their_matches in zip(frames, ours, theirs, matched_people(ours),
                                                           matched_people(theirs), strict=True):
        for truth in sorted(set(our_matches) & set(their_matches)):
            box = mine.truth_boxes[truth]
            head = HEAD_FRACTION_OF_HEIGHT * (box[3] - box[1])
            person = frame[which][our_matches[truth]]
            k = np.asarray(person["keypoints"], float)
            r = np.asarray(ref.keypoints[their_matches[truth]], float)
            states = {}
            for name, (left, right) in zip(PAIR_NAMES, PAIRS, strict=True):
                if min(r[left, 2], r[right, 2]) < REFERENCE_CONFIDENCE:
                    continue
                if np.linalg.norm(r[left, :2] - r[right, :2]) < AGREEMENT_HEAD_SIZES * head:
                    continue
                near = np.linalg.norm(k[[left, right], None, :2] - r[None, [left, right], :2], axis=2) \
                    <= AGREEMENT_HEAD_SIZES * head  # [ours, theirs]
                straight, crossed = int(near[0, 0]) + int(near[1, 1]), int(near[0, 1]) + int(near[1, 0])
                if straight != crossed:
                    states[name] = crossed > straight
            shoulders = abs(r[5, 0] - r[6, 0]) / (box[3] - box[1]) if min(r[5, 2], r[6, 2]) >= 0.5 else np.nan
            yield {"frame": frame["frame"], "states": states, "facing": person.get("facing"),
                   "handedness": person["handedness"], "track": person.get("track"), "shoulders": shoulders,
                   "height": box[3] - box[1],
                   # the reference's facing from its shoulders: its left one on the image's left, seen from behind
                   "reference_behind": bool(r[5, 0] < r[6, 0]) if min(r[5, 2], r[6, 2]) >= 0.5 else None}


def summarise(paths: list[str], which: str) -> None:
    people = [p for path in paths for p in pair_states(pickle.loads(open(path, "rb").read()), which)]
    print(f"{which}: {len(people)} people matched")
    per_pair = collections.Counter()
    per_pair_n = collections.Counter()
    for p in people:
        for name, crossed in p["states"].items():
            per_pair[name] += crossed
            per_pair_n[name] += 1
    print("  pairs the other way round:", {n: f"{per_pair[n]}/{per_pair_n[n]}" for n in PAIR_NAMES})
    patterns = collections.Counter()
    for p in people:
        limbs = {}
        for limb, names in LIMBS.items():
            seen = [c for n, c in p["states"].items() if n in names]
            limbs[limb] = None if not seen else ("x" if all(seen) else "ok" if not any(seen) else "mixed")
        patterns[tuple(sorted((k, v) for k, v in limbs.items() if v is not None))] += 1
    for pattern, count in patterns.most_common(12):
        print(f"  {count:4d} {dict(pattern)}")
    for label, test in (("shoulders < 0.06 h apart (profile)", lambda p: p["shoulders"] < 0.06),
                        ("shoulders >= 0.06 h apart", lambda p: p["shoulders"] >= 0.06)):
        group = [p for p in people if test(p)]
        upper = [c for p in group for n, c in p["states"].items() if n in LIMBS["arms"] | LIMBS["head"]]
        legs = [c for p in group for n, c in p["states"].items() if n in LIMBS["legs"]]
        if upper and legs:
            print(f"  {label}: {len(group)} people; upper pairs other way {np.mean(upper):.2f} of {len(upper)}, "
                  f"leg pairs {np.mean(legs):.2f} of {len(legs)}")
    for source in sorted({p["facing"] for p in people}):
        group = [p for p in people if p["facing"] == source]
        upper = [c for p in group for n, c in p["states"].items() if n in {"shoulder", "hip"}]
        print(f"  facing from {source}: {len(group)} people, shoulder+hip pairs other way {np.mean(upper):.2f}"
              f" of {len(upper)}")



def by_track(paths: list[str]) -> None:
    """Per track: how many of its scored people were read the other way round (shoulders and hips)."""
    for path in paths:
        people = list(pair_states(pickle.loads(open(path, "rb").read()), "ours"))
        tracks = collections.defaultdict(list)
        for p in people:
            seen = [c for n, c in p["states"].items() if n in {"shoulder", "hip"}]
            if seen:
                tracks[p["track"]].append((p["frame"], int(np.mean(seen) > 0.5), p["facing"],
                                           round(p["handedness"], 2)))
        print(path, collections.Counter(p["facing"] for p in people))
        for track, rows in sorted(tracks.items()):
            wrong = sum(r[1] for r in rows)
            if wrong:
                print(f"  track {track}: {wrong}/{len(rows)} other way (frame, X: other way, source, reading):",
                      " ".join(f"{f}{'X' if w else '.'}{src[0]}{h:+.1f}" for f, w, src, h in rows))


def sources(paths: list[str]) -> None:
    """Per facing source: people read the reference's way or the other (shoulders and hips), and whether the facing
    model's reading in that frame (what ``handedness`` reports where the walk or the track vote ordered the pairs)
    says what the reference says, surely (|reading| >= 0.5) or not."""
    table = collections.Counter()
    for path in paths:
        for p in pair_states(pickle.loads(open(path, "rb").read()), "ours"):
            seen = [c for n, c in p["states"].items() if n in {"shoulder", "hip"}]
            if not seen or np.mean(seen) == 0.5 or p["reference_behind"] is None:
                continue
            model = "model right" if (p["handedness"] > 0) == p["reference_behind"] else "model wrong"
            table[(p["facing"], "wrong" if np.mean(seen) > 0.5 else "right", model,
                   "sure" if abs(p["handedness"]) >= 0.5 else "unsure")] += 1
    for key, count in sorted(table.items()):
        print(" ", key, count)


if __name__ == "__main__":
    summarise(sys.argv[1:], "ours")
    summarise(sys.argv[1:], "each")
    sources(sys.argv[1:])
    by_track(sys.argv[1:])
