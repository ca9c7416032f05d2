"""The result images people look at: precision-recall curves and training curves (matplotlib, headless).

Every figure is written through a temporary name and renamed, like every other output.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vc.deploy.metrics import Evaluation  # noqa: E402
from vc.io import atomic_path  # noqa: E402


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
