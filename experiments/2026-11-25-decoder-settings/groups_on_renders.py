"""Whether a region's network keeps people in groups apart on its own held-out renders, and what decoding changes.

    python experiments/2026-11-25-decoder-settings/groups_on_renders.py --pair BUNDLE RENDERS
        [--pair BUNDLE RENDERS ...] --region r1 [--variant NAME FIELD=VALUE [FIELD=VALUE ...]]...
        --out experiments/2026-11-25-decoder-settings/results

Each ``--pair`` is a bundle and the ``vc-render`` dataset it was trained on (a compile's ``bundle`` and
``renders``); their held-out shards (the ones training never saw) are run through the bundle's exported model of
``--region`` once, then decoded under each variant of its ``DecodeConfig`` (as ``decode_variants.py``
does on real frames). Real frames hold few people in groups (PETS09's 80 dev frames: 43), so a change to how
groups are decoded or learned moves that recall by whole people; a few seeds' held-out renders hold hundreds.

Per variant: AP50, recall apart and overlapping another (over every detection kept), and of the overlapping
people not found, how many have a detection at IoU 0.3-0.5 that another person took (one box for two). For the
renders as exported, the distance from each overlapping person's centre to their nearest neighbour's, in person
heights, found against not found (``groups_on_renders.png``): the decoder keeps no two centres closer than
``min_centre_separation``. Writes ``groups_on_renders.json``, ``.md`` and ``.png`` to ``--out``.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from decode_variants import parse_variants  # noqa: E402
from tqdm import tqdm  # noqa: E402

from vc.deploy.bundle import RegionEntry, load_bundle  # noqa: E402
from vc.deploy.decode import decode  # noqa: E402
from vc.evaluation.metrics import Evaluation, ImageResult, evaluate, grouped  # noqa: E402
from vc.evaluation.misses import analyse_misses  # noqa: E402
from vc.evaluation.renders import image_result  # noqa: E402
from vc.io import write_json  # noqa: E402
from vc.model.codec import person_height_px  # noqa: E402
from vc.model.precision import crop_sized, session  # noqa: E402
from vc.render.dataset import Sample, open_region, read_sample  # noqa: E402


def held_out_maps(entry: RegionEntry, renders: Path) -> list[tuple[Sample, np.ndarray, np.ndarray]]:
    """(sample, instance mask, heat maps) of every held-out render of ``entry``'s region."""
    data = open_region(renders, entry.name)
    runner = session(entry.model)
    name = runner.get_inputs()[0].name
    crop = (entry.crop_window[2], entry.crop_window[3])
    maps = []
    for sample in tqdm(data.held_out, desc=f"{renders.parent.name} {entry.name}", unit="img"):
        image, instances = read_sample(sample)
        maps.append((sample, instances, runner.run(None, {name: crop_sized(image, crop)[None]})[0][0]))
    return maps


def decoded(cache: list[tuple[RegionEntry, Sample, np.ndarray, np.ndarray]], changes: dict) -> list[ImageResult]:
    """Every cached render's heat maps decoded with ``changes`` to its bundle's ``DecodeConfig``, in the metrics'
    terms."""
    return [image_result(sample.annotations, instances,
                         decode(maps, replace(entry.decode, **changes), entry.expected_height_px), entry.decode.stride)
            for entry, sample, instances, maps in cache]


def measure(images: list[ImageResult], evaluation: Evaluation) -> dict:
    """AP50, recall (every detection kept) of the people apart and of those overlapping another, and how many of
    the latter the miss analysis's operating point leaves unfound, one box for two or otherwise; ``evaluation`` is
    :func:`evaluate` of ``images``."""
    misses = analyse_misses(images, list(range(len(images))))
    overlapping = [p for p in misses.people if p.grouped and p.outcome != "found"] if misses else []
    apart = found_apart = 0
    for image, pairs in zip(images, evaluation.matches, strict=True):
        alone = ~grouped(image.truth_boxes) & ~image.ignored()
        apart += int(alone.sum())
        found_apart += sum(bool(alone[truth]) for truth, _ in pairs)
    return {"ap50": round(evaluation.ap50, 4), "people_apart": apart,
            "recall_apart": round(found_apart / apart, 4) if apart else None,
            "people_overlapping": evaluation.overlapping,
            "recall_overlapping": evaluation.to_dict()["recall_overlapping"],
            "overlapping_not_found_at_the_operating_point": len(overlapping),
            "of_which_one_box_for_two": sum(p.outcome == "near miss" and p.nearest_found_another
                                            for p in overlapping)}


def centre_separations(cache: list[tuple[RegionEntry, Sample, np.ndarray, np.ndarray]], images: list[ImageResult],
                       evaluation: Evaluation) -> tuple[list[float], list[float]]:
    """Distance (person heights) from each overlapping, asked-for person's centre to the nearest other centre:
    for the people found and for those not found (``evaluation``: :func:`evaluate` of ``images``)."""
    found, missed = [], []
    for (_, sample, _, _), image, pairs in zip(cache, images, evaluation.matches, strict=True):
        if len(sample.annotations) < 2:  # (the truth boxes are the annotations, in order: image_result)
            continue
        centres = np.array([a["center"] for a in sample.annotations], float)
        heights = np.array([person_height_px(a) for a in sample.annotations])
        matched = {truth for truth, _ in pairs}
        in_group = grouped(image.truth_boxes) & ~image.ignored()
        for index in np.flatnonzero(in_group):
            distance = np.delete(np.hypot(*(centres - centres[index]).T), index).min() / heights[index]
            (found if index in matched else missed).append(float(distance))
    return found, missed


def _figure(found: list[float], missed: list[float], separation: float, path: Path, title: str) -> None:
    figure, axes = plt.subplots(figsize=(6.4, 3.6))
    bins = np.linspace(0.0, 0.6, 25)
    axes.hist([found, missed], bins=bins, stacked=True, label=[f"found ({len(found)})", f"not found ({len(missed)})"],
              color=["#4c9a6a", "#c8553d"])
    axes.axvline(separation, color="k", linestyle="--", linewidth=1)
    axes.text(separation, axes.get_ylim()[1] * 0.95, " decoder's min. centre separation", va="top", fontsize=8)
    axes.set_xlabel("distance to the nearest other person's centre (person heights)")
    axes.set_ylabel("people overlapping another")
    axes.set_title(title, fontsize=9)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pair", nargs=2, action="append", type=Path, required=True, metavar=("BUNDLE", "RENDERS"))
    parser.add_argument("--region", required=True)
    parser.add_argument("--variant", nargs="+", action="append", metavar="NAME FIELD=VALUE",
                        help="a named variant and the DecodeConfig fields it changes (repeatable)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    cache = []
    for bundle, renders in args.pair:
        entries = [entry for entry in load_bundle(bundle).regions if entry.name == args.region]
        if not entries:
            raise SystemExit(f"{bundle}: no region {args.region!r}")
        cache += [(entries[0], *item) for item in held_out_maps(entries[0], renders)]
    variants = {"as exported": {}, **(parse_variants(args.variant) if args.variant else {})}
    results, exported = {}, None
    for name, changes in variants.items():
        images = decoded(cache, changes)
        evaluation = evaluate(images)
        exported = exported or (images, evaluation)  # the first variant: as exported
        results[name] = {"changes": changes, **measure(images, evaluation)}
        print(f"{name:32s} {json.dumps({k: v for k, v in results[name].items() if k != 'changes'})}")
    found, missed = centre_separations(cache, *exported)
    separation = cache[0][0].decode.min_centre_separation
    args.out.mkdir(parents=True, exist_ok=True)
    _figure(found, missed, separation, args.out / "groups_on_renders.png",
            f"{args.region}: held-out renders of {len(args.pair)} bundle(s), people overlapping another")
    quartiles = {label: [round(float(q), 3) for q in np.percentile(values, [25, 50, 75])] if values else None
                 for label, values in (("found", found), ("not_found", missed))}
    write_json(args.out / "groups_on_renders.json",
               {"pairs": [[str(b), str(r)] for b, r in args.pair], "region": args.region,
                "held_out_samples": len(cache), "variants": results,
                "centre_separation_heights_quartiles": quartiles})
    lines = ["| decoding | AP50 | recall apart | recall overlapping (people) | not found at the operating point | "
             "of which one box for two |", "|---|---|---|---|---|---|"]
    lines += [f"| {name} | {r['ap50']:.3f} | {r['recall_apart']} | {r['recall_overlapping']} "
              f"({r['people_overlapping']}) | {r['overlapping_not_found_at_the_operating_point']} | "
              f"{r['of_which_one_box_for_two']} |" for name, r in results.items()]
    (args.out / "groups_on_renders.md").write_text("\n".join(lines) + "\n")
    print(json.dumps({"written": str(args.out), "centre_separation_heights_quartiles": quartiles}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
