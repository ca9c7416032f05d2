"""Every per-seed pair of a baseline and a change on TUD-Stadtmitte's and PETS09's halves, and every configuration
compiled more than once, gathered from the other experiments' results files (frozen experiment, issue 57).

Three seeds decide every change on the halves (0019). How far a figure moves between a baseline and a change on one
seed's bundle, against how far it moves between seeds, says what three seeds can resolve. A change is one of three
kinds, since each kind draws again what the one before it keeps:

- ``decode``: the same bundles read with other decoder, runtime or tracker settings;
- ``train``: the networks trained again on the same renders (same scene, seed), with other training settings;
- ``render``: other renders (the scene, its priors or the render plan changed), so trained again too.

An experiment is gathered where its files give a baseline and at least one change per seed, with AP50 tracked, on a
half (choosing: PETS09 frames 1-200, TUD-Stadtmitte 1-90; confirming: 201-400, 91-179). Every figure is read from
the files the experiments wrote; where one exists only in a markdown table or in vc-eval's printed summary, that text
is parsed.

    python collect.py      # writes results/pairs.csv and results/repeats.csv

``pairs.csv``: experiment, variant, kind, camera, half, figure, seed, baseline, value, one row per figure both arms
give on one seed's bundle (decode) or compile (train, render) and half. A variant read against another arm than the
experiment's control is named "ARM against BASELINE"; "[COMPILE]" names the compile where an experiment measured
more than one of a camera and seed. ``repeats.csv``: configuration, draw, camera, half, figure, seed, value.
"""

from __future__ import annotations

import csv
import json
import re
from collections import Counter, defaultdict
from collections.abc import Iterable, Iterator
from pathlib import Path

HERE = Path(__file__).parent
EXPERIMENTS = HERE.parent
RESULTS = HERE / "results"

CAMERAS = ("pets", "tud")
FIGURES = ("ap50_tracked", "ap50_each", "pose_each", "pose_tracked")
DECODE, TRAIN, RENDER = "decode", "train", "render"

Key = tuple[str, int, str]  # camera, seed, half
Measured = dict[Key, dict[str, float]]  # figure -> value


def half_of(first_frame: int) -> str:
    return "choosing" if first_frame == 1 else "confirming"


def results(experiment: str) -> Path:
    return EXPERIMENTS / experiment / "results"


# --- one reader per source format --------------------------------------------------------------------------------


def arm_folder(folder: Path, camera: str) -> Measured:
    """``seedS_HALF.json`` (vc-eval's evaluation as each experiment's measure.py wrote it) and, where measured,
    ``pose_seedS_HALF.json`` (tud-denser-crowd's pose.py: "visual compiler" is the tracked reading)."""
    measured: Measured = {}
    for path in folder.glob("seed*_*.json"):
        seed, half = path.stem.removeprefix("seed").split("_")
        run = json.loads(path.read_text())
        measured[camera, int(seed), half] = {"ap50_tracked": run["ap50_tracked"], "ap50_each": run["ap50_each_frame"]}
    for path in folder.glob("pose_seed*_*.json"):
        seed, half = path.stem.removeprefix("pose_seed").split("_")
        pose = json.loads(path.read_text())
        measured[camera, int(seed), half].update(
            pose_tracked=pose["visual compiler"], pose_each=pose["visual compiler, each frame on its own"])
    return measured


def pose_jsonl(path: Path, seed: int | None = None) -> dict[tuple[str | None, str], Measured]:
    """keypoint-model-capacity/measure.py's lines (one per seed and half, each bundle read beside the others), as
    (compile label or None, arm) -> pose agreement; ``seed`` for files whose lines do not name one."""
    arms: dict[tuple[str | None, str], Measured] = defaultdict(dict)
    for line in path.read_text().splitlines():
        record = json.loads(line)
        key = record["camera"], record.get("seed", seed), half_of(record["frames"][0])
        readings = record["readings"]
        for arm in {reading.removesuffix(", tracked") for reading in readings if reading.endswith(", tracked")}:
            arms[record.get("compile"), arm][key] = {"pose_each": readings[f"{arm}, each frame"]["overall"],
                                                     "pose_tracked": readings[f"{arm}, tracked"]["overall"]}
    return arms


def measure_jsonl(path: Path) -> dict[tuple[str, str], Measured]:
    """carried-people/measure.py's lines (fragments-or-hidden's too), as (compile label, variant) -> AP50."""
    arms: dict[tuple[str, str], Measured] = defaultdict(dict)
    for line in path.read_text().splitlines():
        record = json.loads(line)
        arms[record["compile"], record["variant"]][record["camera"], record["seed"], record["half"]] = {
            "ap50_tracked": record["ap50_tracked"], "ap50_each": record["ap50_each_frame"]}
    return arms


def gates_jsonl(path: Path) -> dict[str, Measured]:
    """identities-at-the-real-rate/gates.py's lines (a-gate-for-the-crowd's crowd_gate.py writes the same): every
    arm's AP50 tracked ("ap50") and pose agreement tracked ("pose") by seed and half."""
    arms: dict[str, Measured] = defaultdict(dict)
    for line in path.read_text().splitlines():
        record = json.loads(line)
        for arm, reading in record.items():
            if isinstance(reading, dict):
                arms[arm][record["camera"], record["seed"], record["half"]] = {
                    "ap50_tracked": reading["ap50"], "pose_tracked": reading["pose"]}
    return arms


def range_v2_json(path: Path) -> dict[str, Measured]:
    """camera-range-v2-every-frame's ``clean_every_frame``: arm -> camera -> half -> figure -> seeds 0, 1, 2."""
    arms: dict[str, Measured] = defaultdict(dict)
    for arm, cameras in json.loads(path.read_text())["clean_every_frame"].items():
        for camera, halves in cameras.items():
            for half in ("choosing", "confirming"):  # "dev" (frames 1-400) is both halves together
                for seed, (tracked, each) in enumerate(zip(halves[half]["tracked"], halves[half]["each_frame"],
                                                           strict=True)):
                    arms[arm][camera, seed, half] = {"ap50_tracked": tracked, "ap50_each": each}
    return arms


def snow_and_light_json(path: Path) -> Measured:
    """snow-and-light's ``every_frame.json``: camera -> "seed S" -> half -> tracked / each_frame."""
    measured: Measured = {}
    for camera, seeds in json.loads(path.read_text()).items():
        for seed, halves in seeds.items():
            for half in ("choosing", "confirming"):
                measured[camera, int(seed.removeprefix("seed ")), half] = {
                    "ap50_tracked": halves[half]["tracked"], "ap50_each": halves[half]["each_frame"]}
    return measured


def facing_arm_json(path: Path) -> dict[str, Measured]:
    """facing-from-the-crop's ``facing_arm.json``: "CAMERA/HALF/SEED" -> arm -> vc-eval's figures."""
    arms: dict[str, Measured] = defaultdict(dict)
    for where, readings in json.loads(path.read_text()).items():
        camera, half, seed = where.split("/")
        for arm, reading in readings.items():
            arms[arm][camera, int(seed), half] = {
                "ap50_tracked": reading["ap50_tracked"], "ap50_each": reading["ap50_each_frame"],
                "pose_tracked": reading["pose_tracked"], "pose_each": reading["pose_each_frame"]}
    return arms


def markdown_rows(path: Path) -> list[dict[str, str]]:
    """The rows of the one markdown table in ``path``, as header -> cell."""
    lines = [line.strip().strip("|") for line in path.read_text().splitlines() if line.startswith("|")]
    header = [cell.strip() for cell in lines[0].split("|")]
    return [dict(zip(header, (cell.strip() for cell in line.split("|")), strict=True)) for line in lines[2:]]


VC_EVAL_LINES = {  # vc-eval's printed summary; "visual compiler" alone is the tracked output
    "ap50_tracked": re.compile(r"^\s*visual compiler\s+AP50 (\d\.\d+)"),
    "ap50_each": re.compile(r"^\s*visual compiler, each frame on its own AP50 (\d\.\d+)"),
    "pose_tracked": re.compile(r"agreement with .*: visual compiler (\d\.\d+) \("),
    "pose_each": re.compile(r"agreement with .*: visual compiler, each frame on its own (\d\.\d+) \("),
}


def vc_eval_text(path: Path) -> dict[str, dict[str, float]]:
    """vc-eval's printed summaries in ``path``, by the output folder each names ("vc-eval: ... -> NAME")."""
    runs: dict[str, dict[str, float]] = {}
    for line in path.read_text().splitlines():
        if line.startswith("vc-eval:"):
            run = runs[line.split("-> ")[-1].rsplit("/", 1)[-1]] = {}
        for figure, pattern in VC_EVAL_LINES.items():
            if match := pattern.search(line):
                run[figure] = float(match.group(1))
    return runs


def merged(*parts: Measured) -> Measured:
    """The figures of several sources of one arm, by camera, seed and half."""
    out: Measured = defaultdict(dict)
    for part in parts:
        for key, figures in part.items():
            out[key].update(figures)
    return out


# --- pairs -------------------------------------------------------------------------------------------------------


def pairs(experiment: str, variant: str, kind: str, baseline: Measured, measured: Measured) -> Iterator[list]:
    """One row per figure that both arms give on the same camera, seed and half."""
    for key in sorted(baseline.keys() & measured.keys()):
        camera, seed, half = key
        for figure in FIGURES:
            if figure in baseline[key] and figure in measured[key]:
                yield [experiment, variant, kind, camera, half, figure, seed, baseline[key][figure],
                       measured[key][figure]]


def folder_pairs(experiment: str, kind: str, camera: str, baseline: Measured, arms: Iterable[str],
                 under: str = "", label: str = "") -> Iterator[list]:
    """Each arm's folder ``results/UNDER/ARM`` against ``baseline``, the variant named ``ARM LABEL``."""
    for arm in arms:
        measured = arm_folder(results(experiment) / under / arm, camera)
        yield from pairs(experiment, f"{arm} {label}".strip(), kind, baseline, measured)


def arm_names(folder: Path, leaving_out: str = "") -> list[str]:
    """The arms' folders in ``folder``, but ``leaving_out`` (the baseline's)."""
    return sorted(path.name for path in folder.iterdir() if path.is_dir() and path.name != leaving_out)


def cut_people() -> Iterator[list]:
    """decode: edge_variants.py clips each person's box to the frame in the runtime's last step, and
    carried_past_edge.py drops carried people whose feet have left it; the bundles are untouched. TUD-Stadtmitte's
    seed 0 has two bundles (0014's range, and today's range tud_wx0)."""
    e = "2026-11-29-cut-people"
    for camera, under, label in (("pets", "pets", ""), ("tud", "tud", ""), ("tud", "tud_range_seed0", "[tud_wx0]")):
        yield from folder_pairs(e, DECODE, camera, arm_folder(results(e) / under / "as_shipped", camera),
                                ["clipped"], under, label)
    for camera in CAMERAS:
        baseline = arm_folder(results(e) / "carried" / camera / "runtime_0020", camera)
        yield from folder_pairs(e, DECODE, camera, baseline, ["carried_within"], f"carried/{camera}")


def decisions_on_halves() -> Iterator[list]:
    """decode: recheck.py reads each variant from a copy of the bundle whose regions' decode fields differ, or with
    the runtime's seam rules or TrackingConfig patched in the process. render: pets_r2_48px is each seed's bundle
    with r2 rendered again at 48 px and retrained (near_region.py)."""
    e = "2026-11-29-decisions-on-halves"
    for camera, under, label in (("pets", "pets", ""), ("tud", "tud", ""), ("tud", "tud_range_seed0", "[tud_wx0]")):
        folder = results(e) / under
        yield from folder_pairs(e, DECODE, camera, arm_folder(folder / "today", camera), arm_names(folder, "today"),
                                under, label)
    today = arm_folder(results(e) / "pets" / "today", "pets")
    yield from pairs(e, "r2 planned at 48 px", RENDER, today, arm_folder(results(e) / "pets_r2_48px" / "today", "pets"))


def a_walk_that_is_not_a_walk() -> Iterator[list]:
    """decode: tracker_arms.py tracks the same facing bundles with the walk's growth limit or a size gate in the
    association. Its seeds are only in results/tracker_arms.md (per-seed AP50 and pose tracked columns)."""
    e = "2026-11-30-a-walk-that-is-not-a-walk"
    arms: dict[str, Measured] = defaultdict(dict)
    for row in markdown_rows(results(e) / "tracker_arms.md"):
        camera, half = row["camera, half"].split()[0], row["camera, half"].split("(")[1].rstrip(")")
        seeds = zip(row["per seed AP50 tracked"].split(" / "), row["per seed pose tracked"].split(" / "), strict=True)
        for seed, (ap50, pose) in enumerate(seeds):
            arms[row["arm"]][camera, seed, half] = {"ap50_tracked": float(ap50), "pose_tracked": float(pose)}
    for arm, measured in arms.items():
        if arm != "control":
            yield from pairs(e, arm, DECODE, arms["control"], measured)


def camera_range_v2() -> Iterator[list]:
    """train: v2 (range_v2.patch) compiled on the control's renders of the same seed; snow-and-light the same
    patch without its shake change, against the every-frame experiment's control."""
    e = "2026-11-30-camera-range-v2-every-frame"
    arms = range_v2_json(results(e) / "every_frame.json")
    yield from pairs(e, "v2", TRAIN, arms["today"], arms["v2"])
    snow = "2026-11-30-snow-and-light"
    snow_and_light = snow_and_light_json(results(snow) / "every_frame.json")
    yield from pairs(snow, "snow and light", TRAIN, arms["today"], snow_and_light)


def cut_box() -> Iterator[list]:
    """decode: cut_box.py changes the runtime's box for people the side cuts, and owns feet beyond the frame."""
    e = "2026-11-30-cut-box"
    folder = results(e) / "tud"
    yield from folder_pairs(e, DECODE, "tud", arm_folder(folder / "before", "tud"), arm_names(folder, "before"), "tud")


def facing_from_the_crop() -> Iterator[list]:
    """train: a facing model trained on the control's own renders is added to a copy of the bundle (its region
    networks unchanged, so its boxes and AP50 are the control's by construction); two arms also change how the
    tracker weighs it against the walk."""
    e = "2026-11-30-facing-from-the-crop"
    arms = facing_arm_json(results(e) / "facing_arm.json")
    for arm in ("facing", "facing_walk", "facing_networks_trusted"):
        yield from pairs(e, arm, TRAIN, arms["control"], arms[arm])


def walkers_scene_compiled() -> Iterator[list]:
    """render: PETS09's scene with the camera solved from its walkers (a fourth region planned), compiled against
    the Tsai scene's bundles of the same seed. Its halves are only in results/halves.md."""
    e = "2026-11-30-walkers-scene-compiled"
    tsai: Measured = defaultdict(dict)
    walkers: Measured = defaultdict(dict)
    figures = {"tracked": "ap50_tracked", "each frame": "ap50_each"}
    for row in markdown_rows(results(e) / "halves.md"):
        if row["seed"] != "mean":
            key = "pets", int(row["seed"]), half_of(int(row["frames"].split("-")[0]))
            tsai[key][figures[row["AP50"]]] = float(row["Tsai scene"])
            walkers[key][figures[row["AP50"]]] = float(row["walkers' scene"])
    yield from pairs(e, "walkers' camera", RENDER, tsai, walkers)


def tud_crowd_5() -> Measured:
    """The control of the 0032 scene's experiments: crowd_5's bundles, with their pose agreement."""
    return arm_folder(results("2026-12-01-tud-denser-crowd") / "crowd_5", "tud")


def denser_crowd_and_people_in_front() -> Iterator[list]:
    """render: the scene's m2_per_person 10 -> 5 (tud-denser-crowd), and in_front.patch's prior placing people
    between a region and the camera (people-in-front, against crowd_5): both change what is rendered."""
    e = "2026-12-01-tud-denser-crowd"
    yield from pairs(e, "crowd_5", RENDER, arm_folder(results(e) / "crowd_10", "tud"), tud_crowd_5())
    e = "2026-12-01-people-in-front"
    yield from folder_pairs(e, RENDER, "tud", tud_crowd_5(), ["in_front"])


def foot_anchor() -> Iterator[list]:
    """decode: fine_peaks.py decodes the same bundles with peaks found on the fine centre map."""
    e = "2026-12-01-foot-anchor"
    yield from folder_pairs(e, DECODE, "tud", arm_folder(results(e) / "coarse", "tud"), ["fine"])


def visible_anchor() -> Iterator[list]:
    """train: r0 trained again on the same renders with its peak at the visible centroid or the head (anchors.py),
    or a head network beside today's r0 (second_look_*); decode: control_* decode today's bundle otherwise, and
    head_size_* / visible_w4_centre decode the head_size / visible_w4 networks otherwise. head_size and its
    agree0.15 and second_look_size arms have seeds 1 and 2 too (measured for head-beside-centre)."""
    e = "2026-12-01-visible-anchor"
    folder = results(e)
    control = tud_crowd_5()
    for arm in arm_names(folder):
        yield from folder_pairs(e, DECODE if arm.startswith("control_") else TRAIN, "tud", control, [arm])
    for network in ("head_size", "visible_w4"):
        arms = [arm for arm in arm_names(folder, network) if arm.startswith(f"{network}_")]
        yield from folder_pairs(e, DECODE, "tud", arm_folder(folder / network, "tud"), arms,
                                label=f"against {network}")


def head_beside_centre_and_small_head() -> Iterator[list]:
    """train: every arm adds a head network trained on the same renders beside today's r0 (union_*, small-head's
    narrower one), or trains r0 again with a head and a size map (both_*, budget_*); decode: both_* and budget_*'s
    head-map people are the same network's maps read otherwise than its *_centre_only arm."""
    e = "2026-12-01-head-beside-centre"
    folder = results(e)
    yield from folder_pairs(e, TRAIN, "tud", tud_crowd_5(), arm_names(folder))
    for network in ("both_centre_only", "budget_centre_only"):
        arms = [arm for arm in arm_names(folder, network) if arm.startswith(network.split("_")[0] + "_")]
        yield from folder_pairs(e, DECODE, "tud", arm_folder(folder / network, "tud"), arms, label=f"against {network}")
    yield from folder_pairs("2026-12-01-small-head", TRAIN, "tud", tud_crowd_5(), ["small_samehead0.1"])


def tracker_gates() -> Iterator[list]:
    """decode: gates.py and crowd_gate.py feed one bundle's people to a tracker per arm (association gates, memory)."""
    for e in ("2026-12-02-identities-at-the-real-rate", "2026-12-02-a-gate-for-the-crowd"):
        arms = gates_jsonl(results(e) / "arms.jsonl")
        for arm, measured in arms.items():
            if arm != "as shipped":
                yield from pairs(e, arm, DECODE, arms["as shipped"], measured)


def tracking_rate() -> Iterator[list]:
    """decode: vc-eval of PETS09's seed-0 bundle tracked at 7 frames/s against the 10 it is tracked at (0046)."""
    e = "2026-12-02-small-people-voted"
    runs = vc_eval_text(results(e) / "vc_eval_pets0_rates.txt")
    for first in (1, 201):
        yield from pairs(e, "tracked at 7 frames/s", DECODE, {("pets", 0, half_of(first)): runs[f"ev_{first}_10"]},
                         {("pets", 0, half_of(first)): runs[f"ev_{first}_7"]})


def pose_weight() -> Iterator[list]:
    """train: retrain.py trains every region again on the compile's renders with the pose loss weight 5 or 20 (10
    reproduces the shipped networks byte for byte). Seed 0, choosing halves, vc-eval's printed summaries only."""
    e = "2026-12-02-pose-weight"
    for camera in CAMERAS:
        runs = {arm: vc_eval_text(results(e) / f"ev_{camera}0_{arm}_1.txt")[f"ev_{camera}0_{arm}_1"]
                for arm in ("control", "pose5", "pose20")}
        key = camera, 0, "choosing"
        for arm in ("pose5", "pose20"):
            yield from pairs(e, arm, TRAIN, {key: runs["control"]}, {key: runs[arm]})


def second_person() -> Iterator[list]:
    """train: r0 and r1 trained again on the same renders with the three behind maps (behind_none: the maps not
    read); decode: behind_0.3 / 0.5 read those networks' maps, against behind_none. Seed 0; pose.jsonl's "behind"
    is behind_0.3."""
    e = "2026-12-03-second-person"
    pose = pose_jsonl(results(e) / "pose.jsonl", seed=0)
    today = merged(arm_folder(results(e) / "today", "tud"), pose[None, "today"])
    behind = {"behind_0.3": merged(arm_folder(results(e) / "behind_0.3", "tud"), pose[None, "behind"])}
    for arm in ("behind_none", "behind_0.5"):
        behind[arm] = arm_folder(results(e) / arm, "tud")
    for arm, measured in behind.items():
        yield from pairs(e, arm, TRAIN, today, measured)
    for arm in ("behind_0.3", "behind_0.5"):
        yield from pairs(e, f"{arm} against behind_none", DECODE, behind["behind_none"], behind[arm])


def behind_continues_a_track() -> Iterator[list]:
    """train: the winter compiles' r0 and r1 trained again on the same renders with the behind maps (maps_not_read
    reads them as today); decode: weak_* add the people behind as weak people, against maps_not_read."""
    e = "2026-12-04-behind-continues-a-track"
    folder = results(e)
    yield from folder_pairs(e, TRAIN, "tud", arm_folder(folder / "today", "tud"), arm_names(folder, "today"))
    yield from folder_pairs(e, DECODE, "tud", arm_folder(folder / "maps_not_read", "tud"), ["weak_0.3", "weak_0.5"],
                            label="against maps_not_read")


def runtime_probes() -> Iterator[list]:
    """decode: feet-beyond-the-edge's edge.py treats the walkable area's far edge as a seam in the runtime;
    hidden-people-carried's HiddenTracker carries covered tracks longer. Both on the winter bundles."""
    e = "2026-12-04-feet-beyond-the-edge"
    for camera in CAMERAS:
        yield from folder_pairs(e, DECODE, camera, arm_folder(results(e) / f"{camera}_today", camera),
                                [f"{camera}_edge"])
    e = "2026-12-04-hidden-people-carried"
    yield from folder_pairs(e, DECODE, "tud", arm_folder(results(e) / "tud_today", "tud"),
                            arm_names(results(e), "tud_today"))


def winter_clothing() -> Iterator[list]:
    """render: priors.clothing: winter in each camera's scene, against the default wardrobe (mixed)."""
    e = "2026-12-04-winter-clothing"
    pose = pose_jsonl(results(e) / "pose.jsonl")
    mixed, winter = (merged(*(arm_folder(results(e) / f"{camera}_{arm}", camera) for camera in CAMERAS),
                            pose[None, arm]) for arm in ("mixed", "winter"))
    yield from pairs(e, "winter", RENDER, mixed, winter)


def tud_winter() -> Measured:
    """winter-clothing's TUD-Stadtmitte winter bundles with their pose: the control of the 0053 scene's experiments."""
    e = "2026-12-04-winter-clothing"
    return merged(arm_folder(results(e) / "tud_winter", "tud"), pose_jsonl(results(e) / "pose.jsonl")[None, "winter"])


def tud_obstacles() -> Iterator[list]:
    """render: the scene's layout drawn with obstacles and/or the walkable ground trimmed, against the winter
    bundles of the same seed (the same priors, the recipe's rectangle and no obstacles)."""
    e = "2026-12-04-tud-obstacles"
    pose = pose_jsonl(results(e) / "pose.jsonl")
    for arm in ("obstacles", "obstacles_only", "trimmed_only"):
        measured = merged(arm_folder(results(e) / f"tud_{arm}", "tud"), pose[None, arm])
        yield from pairs(e, arm, RENDER, tud_winter(), measured)


def carried_people() -> Iterator[list]:
    """decode: measure.py and pose.py track each compile's people with other TrackingConfig settings for the people
    it carries. TUD-Stadtmitte's compiles: tud-obstacles' trimmed_only (seeds 0-2) and obstacles_only (1, 2), the
    recipe's seed 0."""
    e = "2026-12-05-carried-people"
    pose: dict[tuple[str | None, str], Measured] = {}
    arms: dict[tuple[str, str], Measured] = {}
    for name in ("pets", "tud", "tud_recipe"):
        arms.update(measure_jsonl(results(e) / f"{name}.jsonl"))
        pose.update(pose_jsonl(results(e) / f"pose_{name}.jsonl"))
    for (compile_, variant), measured in arms.items():
        if variant != "shipped":
            label = "" if compile_ == "example_scene" else f" [{compile_}]"
            shipped = merged(arms[compile_, "shipped"], pose.get((compile_, "shipped"), {}))
            yield from pairs(e, variant + label, DECODE, shipped, merged(measured, pose.get((compile_, variant), {})))


def fragments_or_hidden() -> Iterator[list]:
    """decode: measure.py drops carried boxes a seen person at the same depth overlaps, with today's carrying
    (against shipped) and with carried-people's longer one (against coast_1.0s_iou_0.8, whose own pair with shipped
    is carried-people's). Choosing half only. Its lines record seed 0 for every compile: the seed is the compile
    label's last digit (tudm0, tudob1, tudob2, tudtr0-2)."""
    e = "2026-12-05-fragments-or-hidden"
    arms = {(compile_, variant): {(camera, int(compile_[-1]), half): figures
                                  for (camera, _, half), figures in measured.items()}
            for (compile_, variant), measured in measure_jsonl(results(e) / "tud.jsonl").items()}
    longer = "coast_1.0s_iou_0.8"
    for (compile_, variant), measured in arms.items():
        if "depth" in variant:
            baseline = longer if variant.startswith(longer) else "shipped"
            name = variant if baseline == "shipped" else f"{variant} against {baseline}"
            yield from pairs(e, f"{name} [{compile_}]", DECODE, arms[compile_, baseline], measured)


EXPERIMENT_PAIRS = (cut_people, decisions_on_halves, a_walk_that_is_not_a_walk, camera_range_v2, cut_box,
                    facing_from_the_crop, walkers_scene_compiled, denser_crowd_and_people_in_front, foot_anchor,
                    visible_anchor, head_beside_centre_and_small_head, tracker_gates, tracking_rate, pose_weight,
                    second_person, behind_continues_a_track, runtime_probes, winter_clothing, tud_obstacles,
                    carried_people, fragments_or_hidden)


# --- repeats -----------------------------------------------------------------------------------------------------


def repeats() -> Iterator[list]:
    """results-as-shipped compiled PETS09's example scene and TUD-Stadtmitte's recipe as they ship; winter-clothing
    compiled copies that say the same (PETS09's differs by a comment: scene hashes 7303b955860d and ab1c8be95f61).
    A compile draws its renders from the scene file's bytes and the seed, so each pair is two draws of one
    configuration (results-as-shipped's README)."""
    shipped = results("2026-12-05-results-as-shipped")
    winter = results("2026-12-04-winter-clothing")
    configurations = {"pets": "PETS09 example scene, winter clothing (0053)",
                      "tud": "TUD-Stadtmitte recipe of docs/results.md, winter clothing (0053)"}
    draws = {"shipped": merged(*(arm_folder(shipped / camera, camera) for camera in CAMERAS),
                               *(pose_jsonl(shipped / f"pose_{camera}.jsonl")[None, "shipped"] for camera in CAMERAS)),
             "copy": merged(*(arm_folder(winter / f"{camera}_winter", camera) for camera in CAMERAS),
                            pose_jsonl(winter / "pose.jsonl")[None, "winter"])}
    for draw, measured in draws.items():
        for (camera, seed, half), figures in sorted(measured.items()):
            yield from ([configurations[camera], draw, camera, half, figure, seed, figures[figure]]
                        for figure in FIGURES if figure in figures)


def write(name: str, header: list[str], rows: list[list], key_columns: int) -> None:
    """``results/NAME``, after checking that no two rows are one measurement (the columns before the values)."""
    doubled = [key for key, count in Counter(tuple(row[:key_columns]) for row in rows).items() if count > 1]
    assert not doubled, f"{name}: rows measured twice: {doubled[:3]}"
    with open(RESULTS / name, "w", newline="") as out:
        csv.writer(out).writerows([header, *rows])


def main() -> None:
    pair_rows = [row for experiment in EXPERIMENT_PAIRS for row in experiment()]
    write("pairs.csv", ["experiment", "variant", "kind", "camera", "half", "figure", "seed", "baseline", "value"],
          pair_rows, 7)
    write("repeats.csv", ["configuration", "draw", "camera", "half", "figure", "seed", "value"], list(repeats()), 6)
    print(f"pairs.csv: {len(pair_rows)} rows; repeats.csv written")


if __name__ == "__main__":
    main()
