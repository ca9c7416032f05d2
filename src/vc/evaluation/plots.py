"""The result images people look at: precision-recall curves, training curves, lighting and miss analyses
(matplotlib, headless).

Every figure is written through a temporary name and renamed, like every other output.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vc.evaluation.agreement import PoseAgreement  # noqa: E402
from vc.evaluation.metrics import Evaluation  # noqa: E402
from vc.evaluation.misses import NEAR_IOU, OUTCOMES, MissAnalysis  # noqa: E402
from vc.io import atomic_path  # noqa: E402
from vc.keypoints import COCO_KEYPOINTS  # noqa: E402


def _save(figure: plt.Figure, destination: Path) -> None:
    with atomic_path(destination) as temporary:
        figure.savefig(temporary, dpi=110, format="png")
    plt.close(figure)


def plot_precision_recall(curves: Mapping[str, Evaluation], destination: Path, title: str) -> None:
    """One precision-recall curve per entry, labelled with its AP50 (and PCKh when there is one)."""
    figure, axes = plt.subplots(figsize=(5.5, 4.5))
    for label, evaluation in curves.items():
        envelope = np.maximum.accumulate(evaluation.precision[::-1])[::-1] if len(evaluation.precision) else []
        text = f"{label}: AP50 {evaluation.ap50:.3f}"
        if evaluation.pckh is not None:
            text += f", PCKh {evaluation.pckh:.3f}"
        axes.plot(evaluation.recall, envelope, label=text)
    axes.set(xlabel="recall", ylabel="precision", xlim=(0, 1.01), ylim=(0, 1.01), title=title)
    axes.grid(alpha=0.3)
    axes.legend(loc="lower left", fontsize=8)
    figure.tight_layout()
    _save(figure, destination)


def plot_training_curve(steps: list[int], losses: list[float], destination: Path, title: str) -> None:
    """Training loss against step (log scale: the interesting part is the last decade)."""
    figure, axes = plt.subplots(figsize=(5.5, 3.5))
    axes.plot(steps, losses)
    axes.set(xlabel="step", ylabel="loss", yscale="log", title=title)
    axes.grid(alpha=0.3, which="both")
    figure.tight_layout()
    _save(figure, destination)


def plot_lighting_comparison(background: np.ndarray, rerender: np.ndarray, log_error: np.ndarray,
                             region_outlines: Mapping[str, list[np.ndarray]], region_errors: Mapping[str, float | None],
                             destination: Path, title: str, tolerance: float = 0.10) -> None:
    """The background, the empty scene re-rendered under the estimated light (both 8-bit RGB), the re-render's
    error on known ground (``log_error``: log2 of re-render over background, NaN elsewhere) with the regions
    drawn, and each region's median error against ``tolerance``."""
    figure, axes = plt.subplots(2, 2, figsize=(13, 8.6), gridspec_kw={"height_ratios": [1, 1]})
    (top_left, top_right), (bottom_left, bottom_right) = axes
    top_left.imshow(background)
    top_left.set_title("background (the camera's image)")
    top_right.imshow(rerender)
    top_right.set_title("empty scene re-rendered under the estimate")
    grey = background.mean(axis=-1) / 255.0
    bottom_left.imshow(grey, cmap="gray", vmin=0, vmax=1.6)
    shown = bottom_left.imshow(np.clip(log_error, -1, 1), cmap="RdBu_r", vmin=-1, vmax=1)
    for index, (name, outlines) in enumerate(region_outlines.items()):
        colour = plt.cm.tab10(index % 10)
        for outline in outlines:
            bottom_left.plot(*np.vstack([outline, outline[:1]]).T, color=colour, lw=1.2)
        if outlines:
            x, y = outlines[0].mean(axis=0)
            bottom_left.text(x, y, name, color="black", fontsize=10, ha="center", va="center",
                             bbox={"facecolor": colour, "alpha": 0.8, "pad": 1.5})
    bottom_left.set_title("re-render / background on known ground (log2; red: re-render brighter)")
    figure.colorbar(shown, ax=bottom_left, fraction=0.03, pad=0.01, ticks=[-1, -0.5, 0, 0.5, 1])
    names = list(region_errors)
    values = [100 * (region_errors[name] or 0.0) for name in names]
    bars = bottom_right.bar(names, values, color=[plt.cm.tab10(i % 10) for i in range(len(names))])
    for bar, name in zip(bars, names, strict=True):
        label = "no ground" if region_errors[name] is None else f"{region_errors[name]:+.1%}"
        bottom_right.annotate(label, (bar.get_x() + bar.get_width() / 2, bar.get_height()), ha="center",
                              va="bottom" if bar.get_height() >= 0 else "top", fontsize=9)
    bottom_right.axhspan(-100 * tolerance, 100 * tolerance, color="green", alpha=0.12,
                         label=f"within {tolerance:.0%}")
    bottom_right.axhline(0, color="black", lw=0.8)
    limit = max(25.0, *(abs(v) * 1.25 for v in values)) if values else 25.0
    bottom_right.set(ylabel="median luminance error per region (%)", ylim=(-limit, limit),
                     title="re-render against background, per region")
    bottom_right.legend(loc="upper right", fontsize=8)
    for axis in (top_left, top_right, bottom_left):
        axis.set_axis_off()
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    _save(figure, destination)


def plot_miss_analysis(analysis: MissAnalysis, destination: Path, title: str, arrivals: dict | None = None) -> None:
    """The operating point's errors (:mod:`vc.evaluation.misses`): outcomes of people apart and in groups, recall by
    height, region and the frame's edge and, given ``arrivals`` (:func:`vc.evaluation.arrivals.summarise`), the share
    of the people coming into view found in their first frame, the near misses' box errors, and the false positives
    by kind."""
    figure, axes = plt.subplots(2, 2, figsize=(11, 8))
    (outcomes_axis, recall_axis), (near_axis, false_axis) = axes
    colours = {"found": "tab:green", "near miss": "tab:orange", "missed": "tab:red"}
    groups = {"apart": analysis.outcomes(False), "overlapping another": analysis.outcomes(True)}
    bottom = np.zeros(len(groups))
    for outcome in OUTCOMES:
        counts = np.array([groups[label][outcome] for label in groups], float)
        outcomes_axis.bar(list(groups), counts, bottom=bottom, color=colours[outcome], label=outcome)
        bottom += counts
    for index, label in enumerate(groups):
        total = sum(groups[label].values())
        if total:
            outcomes_axis.annotate(f"recall {groups[label]['found'] / total:.2f}", (index, bottom[index]),
                                   ha="center", va="bottom", fontsize=9)
    outcomes_axis.set(ylabel="ground-truth people", title="people apart and in groups (IoU >= 0.1 with another)")
    outcomes_axis.legend(fontsize=8)

    rates = {**{f"height {k}": v for k, v in analysis.recall_by_height().items()},
             **{f"region {k}": v for k, v in analysis.recall_by_region().items()},
             **{f"edge: {k}": v for k, v in analysis.recall_by_edge().items()},
             **{f"arriving: {k.split(' at ')[0]}": {"recall": v["found_in_first_frame"] / v["people"],
                                                   "people": v["people"]}
                for k, v in (arrivals or {}).items() if v["people"]}}
    labels = list(rates)
    values = [rates[label]["recall"] or 0.0 for label in labels]
    colours = {"height": "tab:blue", "region": "tab:purple", "edge:": "tab:green", "arriving:": "tab:olive"}
    bars = recall_axis.barh(labels, values, color=[colours[label.split(" ")[0]] for label in labels])
    for bar, label in zip(bars, labels, strict=True):
        recall_axis.annotate(f" {rates[label]['recall']:.2f} of {rates[label]['people']}",
                             (bar.get_width(), bar.get_y() + bar.get_height() / 2), va="center", fontsize=8)
    recall_axis.invert_yaxis()
    recall_axis.set(xlim=(0, 1.25), xlabel="recall",
                    title="recall by height, region, the frame's edge;\narrivals found in their first frame")

    near = [person for person in analysis.people if person.outcome == "near miss"]
    errors = [person.box_error() for person in near]
    for another, colour, label in ((False, "tab:orange", "a misplaced box"), (True, "tab:gray", "a neighbour's box")):
        chosen = [error for error, person in zip(errors, near, strict=True) if person.nearest_found_another == another]
        if chosen:
            near_axis.scatter([e["width_ratio"] for e in chosen], [e["x_offset"] for e in chosen], s=18,
                              color=colour, alpha=0.7, label=f"{label} ({len(chosen)})")
    near_axis.axvline(1.0, color="black", lw=0.8)
    near_axis.axhline(0.0, color="black", lw=0.8)
    near_axis.set(xlabel="width ratio (detection / truth)", ylabel="horizontal offset (truth widths)",
                  title=f"near misses (IoU {NEAR_IOU}-0.5 with a detection): {len(near)}")
    if near:
        near_axis.legend(fontsize=8)

    kinds = analysis.false_positive_kinds()
    false_axis.bar(list(kinds), list(kinds.values()), color="tab:red")
    plt.setp(false_axis.get_xticklabels(), rotation=25, ha="right")
    false_axis.set(ylabel="detections", title=f"false positives by kind: {len(analysis.false_positives)}")
    figure.suptitle(f"{title} — operating point: score >= {analysis.score_threshold:.2f}, precision "
                    f"{analysis.precision:.3f}, recall {analysis.recall:.3f}", fontsize=10)
    figure.tight_layout()
    _save(figure, destination)


def plot_pose_agreement(agreements: Mapping[str, PoseAgreement], destination: Path, title: str) -> None:
    """Per COCO keypoint, the share of a reference pose model's confident keypoints each detector agrees with
    (:mod:`vc.evaluation.agreement`), one bar per detector, its overall share in the legend; below, where each
    detector puts the keypoint against the reference (median offset in head sizes, across and down)."""
    figure, (axes, offsets) = plt.subplots(2, 1, figsize=(10, 8), sharex=True, height_ratios=(3, 2))
    width = 0.8 / max(len(agreements), 1)
    positions = np.arange(len(COCO_KEYPOINTS))
    for index, (name, agreement) in enumerate(agreements.items()):
        values = [np.nan if value is None else value for value in agreement.per_keypoint().values()]
        overall = "n/a" if agreement.overall is None else f"{agreement.overall:.2f}"
        shift = (index - (len(agreements) - 1) / 2) * width
        bars = axes.bar(positions + shift, values, width, label=f"{name}: {overall} overall, {agreement.people} people")
        if agreement.median_offset is not None:
            colour = bars.patches[0].get_facecolor() if bars.patches else None
            offsets.plot(positions + shift, agreement.median_offset[:, 1], "o", color=colour, label=f"{name}: down")
            offsets.plot(positions + shift, agreement.median_offset[:, 0], "x", color=colour, label=f"{name}: across")
    axes.set(ylim=(0, 1.05), ylabel="agreement", title=title)
    axes.grid(alpha=0.3, axis="y")
    axes.legend(fontsize=8, loc="lower left")
    offsets.axhline(0.0, color="black", linewidth=0.8)
    offsets.set(ylabel="median offset from the reference\n(head sizes; + right, + down)")
    offsets.set_xticks(positions, [name.replace("_", " ") for name in COCO_KEYPOINTS], rotation=45, ha="right")
    offsets.grid(alpha=0.3)
    offsets.legend(fontsize=7, ncol=2, loc="best")
    figure.tight_layout()
    _save(figure, destination)
