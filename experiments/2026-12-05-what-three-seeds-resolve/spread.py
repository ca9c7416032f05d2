"""How far one compile's real-frame figures move when nothing but chance changes (frozen experiment, issue 57):
the spread of a compile over its seeds (renders and training drawn again), and of a training over its seeds on one
seed's renders, pooled over the configurations compiled three times.

    python spread.py      # writes results/spread.json and results/spread.md

Its sources are the per-seed files of ../2026-12-05-results-as-shipped (the scenes as they ship),
../2026-12-04-winter-clothing (a copy of PETS09's scene and `winter`/`mixed` compiles of both cameras), and this
experiment's own retrained bundles (``measure.py``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
EXPERIMENTS = HERE.parent
SHIPPED = EXPERIMENTS / "2026-12-05-results-as-shipped" / "results"
WINTER = EXPERIMENTS / "2026-12-04-winter-clothing" / "results"
RESULTS = HERE / "results"

HALVES = ("choosing", "confirming")
FIGURES = ("AP50 tracked", "AP50 each frame", "pose each frame", "pose tracked")
POSE_FRAMES = {"pets": ([1, 200, 5], [201, 400, 5]), "tud": ([1, 90, 1], [91, 179, 1])}
CAMERA_NAMES = {"pets": "PETS09", "tud": "TUD-Stadtmitte"}

Runs = dict[tuple[int, str], dict[str, float]]


def box_runs(folder: Path) -> Runs:
    """``folder/seedS_HALF.json`` (results-as-shipped's and winter-clothing's measurement) by seed and half."""
    runs: Runs = {}
    for path in sorted(folder.glob("seed*_*.json")):
        seed, half = path.stem.removeprefix("seed").split("_")
        result = json.loads(path.read_text())
        runs[int(seed), half] = {"AP50 tracked": result["ap50_tracked"], "AP50 each frame": result["ap50_each_frame"]}
    return runs


def add_pose(runs: Runs, path: Path, camera: str, arm: str, seeds: set[int] | None = None) -> Runs:
    """``runs`` with arm ``arm``'s pose agreement from the keypoint-capacity measurement's lines in ``path``."""
    for line in path.read_text().splitlines():
        record = json.loads(line)
        if record.get("camera", camera) != camera or f"{arm}, tracked" not in record["readings"]:
            continue
        if seeds is not None and record["seed"] not in seeds:
            continue
        key = record["seed"], HALVES[POSE_FRAMES[camera].index(record["frames"])]
        runs.setdefault(key, {})["pose each frame"] = record["readings"][f"{arm}, each frame"]["overall"]
        runs[key]["pose tracked"] = record["readings"][f"{arm}, tracked"]["overall"]
    return runs


def shipped(camera: str) -> Runs:
    """The scene as it ships, seeds 0-2."""
    return add_pose(box_runs(SHIPPED / camera), SHIPPED / f"pose_{camera}.jsonl", camera, "shipped")


def compiles(camera: str) -> dict[str, Runs]:
    """Each configuration's compiles, renders and training both drawn from the seed: the scene as it ships on
    seeds 0-2 and winter-clothing's `winter` arm (the same configuration, from a scene file whose bytes differ, so
    seeds 3-5 stand for its other draw), and winter-clothing's `mixed` arm (0053's control) on seeds 0-2."""
    winter = add_pose(box_runs(WINTER / f"{camera}_winter"), WINTER / "pose.jsonl", camera, "winter")
    return {"as shipped": shipped(camera) | {(seed + 3, half): run for (seed, half), run in winter.items()},
            "mixed clothing": add_pose(box_runs(WINTER / f"{camera}_mixed"), WINTER / "pose.jsonl", camera, "mixed")}


def trainings(camera: str) -> Runs:
    """Seed 0's renders as shipped, trained with seeds 0 (the shipped compile), 1 and 2 (``measure.py``)."""
    runs = {key: value for key, value in shipped(camera).items() if key[0] == 0}
    retrained = add_pose(box_runs(RESULTS / camera), RESULTS / f"pose_{camera}.jsonl", camera, "shipped")
    return runs | {key: value for key, value in retrained.items() if key[0] != 0}


def values(runs: Runs, half: str, figure: str) -> list[float]:
    return [run[figure] for (_, run_half), run in sorted(runs.items()) if run_half == half and figure in run]


def pooled_sd(groups: list[list[float]]) -> tuple[float, int]:
    """The standard deviation of one draw, pooled over groups that each share one configuration, and its degrees
    of freedom."""
    groups = [group for group in groups if len(group) > 1]
    dof = sum(len(group) - 1 for group in groups)
    return float(np.sqrt(sum(np.var(group, ddof=1) * (len(group) - 1) for group in groups) / dof)), dof


def half_correlation(groups: list[Runs], figure: str) -> float:
    """How much a compile that reads high on its choosing half also reads high on its confirming half: the
    correlation of both halves' deviations from their configuration's mean."""
    deviations = []
    for runs in groups:
        seeds = sorted({seed for seed, _ in runs})
        pairs = np.array([[runs[seed, half][figure] for half in HALVES] for seed in seeds])
        deviations.append(pairs - pairs.mean(axis=0))
    stacked = np.concatenate(deviations)
    return float(np.corrcoef(stacked[:, 0], stacked[:, 1])[0, 1])


def measure() -> dict:
    spread = {}
    for camera in CAMERA_NAMES:
        groups = compiles(camera)
        retrained = trainings(camera)
        for figure in FIGURES:
            for half in HALVES:
                compile_sd, compile_dof = pooled_sd([values(runs, half, figure) for runs in groups.values()])
                training = values(retrained, half, figure)
                training_sd = float(np.std(training, ddof=1)) if len(training) > 1 else None
                spread[f"{camera} {half} {figure}"] = {
                    "compiles": {name: values(runs, half, figure) for name, runs in groups.items()},
                    "compile_sd": compile_sd, "compile_dof": compile_dof,
                    "trainings": training, "training_sd": training_sd,
                }
            spread[f"{camera} {figure} half correlation"] = half_correlation(list(groups.values()), figure)
    return spread


def report(spread: dict) -> str:
    lines = ["# One compile's spread (the standard deviation of one draw)", "",
             "| camera, half | figure | compiles, as shipped (six draws); mixed clothing (three) | pooled SD (dof) | "
             "one seed's renders trained again | SD |", "|---|---|---|---|---|---|"]
    for camera, name in CAMERA_NAMES.items():
        for figure in FIGURES:
            for half in HALVES:
                cell = spread[f"{camera} {half} {figure}"]
                drawn = "; ".join(" ".join(f"{v:.3f}" for v in group) for group in cell["compiles"].values())
                trained = " ".join(f"{v:.3f}" for v in cell["trainings"])
                training_sd = "–" if cell["training_sd"] is None else f"{cell['training_sd']:.3f}"
                lines.append(f"| {name} {half} | {figure} | {drawn} | {cell['compile_sd']:.3f} "
                             f"({cell['compile_dof']}) | {trained} | {training_sd} |")
    lines += ["", "Correlation of a compile's choosing and confirming halves (deviations from its configuration's "
              "mean, nine compiles a camera):", ""]
    lines += [f"- {name}, {figure}: {spread[f'{camera} {figure} half correlation']:+.2f}"
              for camera, name in CAMERA_NAMES.items() for figure in FIGURES]
    return "\n".join(lines) + "\n"


def main() -> None:
    spread = measure()
    (RESULTS / "spread.json").write_text(json.dumps(spread, indent=1) + "\n")
    (RESULTS / "spread.md").write_text(report(spread))
    print(report(spread))


if __name__ == "__main__":
    main()
