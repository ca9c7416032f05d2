"""How fast PETS09's annotated people walk, in metres a frame, and so at which frame rate they walk as people do.

Each annotated box's bottom centre is laid on the Tsai ground plane by the scene's camera. A person's step is the
distance between their feet 10 frames apart (10 frames damp the boxes' jitter), divided by 10. Feet within 6 px of
the frame's bottom are left out (the box is cut there, so its bottom is not the feet). Reported: the median step
over every pair of frames, and the median of each person's own median (so that a person seen long does not count
more), each as a speed at 7 and at 10 frames/s.

    PYTHONPATH=src python experiments/2026-12-02-pets09-time-base/speed.py > .../results/speed.json
"""
import json
import sys

import numpy as np

from vc.scenes.loader import load_scene

SCENE = "examples/scenes/pets09_s2l1/scene.yaml"
GROUND_TRUTH = "../shared/data/pets09_s2l1/gt_dev_frames_0001-0400.txt"
GAP = 10  # frames between the two feet of one step
CUT_BELOW_PX = 570  # feet lower than this are at the frame's bottom edge (576 rows)
RATES = (7.0, 10.0)


def steps_by_person(camera, rows: np.ndarray) -> dict[int, np.ndarray]:
    """Metres a frame for each person, over every pair of their frames GAP apart with both feet in the frame."""
    feet = np.c_[rows[:, 2] + rows[:, 4] / 2, rows[:, 3] + rows[:, 5]]
    ground = camera.ground_from_pixels(feet).points[:, :2]
    steps = {}
    for person in np.unique(rows[:, 1]).astype(int):
        mine = np.flatnonzero(rows[:, 1] == person)
        by_frame = {int(rows[i, 0]): i for i in mine}
        moved = [np.linalg.norm(ground[by_frame[f + GAP]] - ground[i]) / GAP
                 for f, i in by_frame.items()
                 if f + GAP in by_frame and max(feet[i, 1], feet[by_frame[f + GAP], 1]) < CUT_BELOW_PX]
        if moved:
            steps[person] = np.asarray(moved)
    return steps


def main() -> None:
    camera = load_scene(SCENE).camera
    rows = np.loadtxt(GROUND_TRUTH, delimiter=",")
    steps = steps_by_person(camera, rows)
    every = np.concatenate(list(steps.values()))
    per_person = np.array([np.median(s) for s in steps.values()])
    report = {"people": len(steps), "steps": int(every.size),
              "m_per_frame": {"every_step_median": float(np.median(every)),
                              "every_step_p25_p75": np.percentile(every, [25, 75]).tolist(),
                              "per_person_median": float(np.median(per_person)),
                              "per_person_p25_p75": np.percentile(per_person, [25, 75]).tolist()}}
    report["m_per_s"] = {f"{rate:g}": {key: (np.asarray(value) * rate).round(3).tolist()
                                       for key, value in report["m_per_frame"].items()} for rate in RATES}
    json.dump(report, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
