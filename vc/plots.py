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
