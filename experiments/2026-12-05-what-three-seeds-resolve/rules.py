"""How often a rule keeps a change whose true effect is known, given the spread ``spread.py`` measured (frozen
experiment, issue 57): the choosing and confirming rule of decision 0019 (level within 0.002) against rules whose
level band is the standard error of the difference, at three and at six seeds.

    python rules.py      # after spread.py; writes results/rules.md and results/keep_probability.png

A change's per-seed difference from what it replaces, on each camera and half, is drawn as its true effect plus
noise: for a change that trains the networks again, two independent compiles' noise (each the pooled spread of one
compile, ``compile_sd``), the two halves of one seed correlated as the compiles' halves are; for a change that only
reads the same bundles another way, the per-seed differences ``pairs.py`` measured.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RESULTS = Path(__file__).parent / "results"
CAMERAS = ("pets", "tud")
FIGURE = "AP50 tracked"
EFFECTS = np.round(np.arange(-0.03, 0.0301, 0.0025), 4)
TRIALS = 100_000
TODAY_LEVEL = 0.002


@dataclass(frozen=True)
class Noise:
    """One camera's per-seed difference noise: its standard deviation on each half and their correlation."""

    choosing: float
    confirming: float
    correlation: float


@dataclass(frozen=True)
class Rule:
    name: str
    seeds: int
    level: str  # "fixed": within TODAY_LEVEL; "error": within twice the standard error of the mean difference
    more_seeds: int = 0  # where ``seeds`` neither keep nor drop the change (no loss, no gain), the seeds run in all


RULES = (Rule("0019: level within 0.002, three seeds", 3, "fixed"),
         Rule("level within two standard errors, three seeds", 3, "error"),
         Rule("level within two standard errors, six seeds", 6, "error"),
         Rule("two standard errors, three seeds, six where three leave it level", 3, "error", more_seeds=6))


def retraining_noise(spread: dict) -> dict[str, Noise]:
    """A retrained change's difference: two compiles, each with the pooled spread of one."""
    return {camera: Noise(np.sqrt(2) * spread[f"{camera} choosing {FIGURE}"]["compile_sd"],
                          np.sqrt(2) * spread[f"{camera} confirming {FIGURE}"]["compile_sd"],
                          spread[f"{camera} {FIGURE} half correlation"]) for camera in CAMERAS}


def per_seed_differences(noise: Noise, effect: float, seeds: int, rng: np.random.Generator) -> np.ndarray:
    """TRIALS x seeds x 2 (choosing, confirming): each seed's difference."""
    sd = np.array([noise.choosing, noise.confirming])
    covariance = np.outer(sd, sd) * np.array([[1, noise.correlation], [noise.correlation, 1]])
    return rng.multivariate_normal([effect, effect], covariance, size=(TRIALS, seeds))


def verdicts(rule: Rule, seeds: int, differences: dict[str, np.ndarray], noises: dict[str, Noise]
             ) -> tuple[np.ndarray, np.ndarray]:
    """(kept, lost) for each trial on its first ``seeds`` seeds: chosen where the change gains beyond the level on
    one camera's choosing half, lost where it loses beyond it on any half."""
    chosen_somewhere = np.zeros(TRIALS, bool)
    lost = np.zeros(TRIALS, bool)
    for camera, noise in noises.items():
        means = differences[camera][:, :seeds].mean(axis=1)
        if rule.level == "fixed":
            level = np.array([TODAY_LEVEL, TODAY_LEVEL])
        else:
            level = 2 * np.array([noise.choosing, noise.confirming]) / np.sqrt(seeds)
        chosen_somewhere |= means[:, 0] > level[0]
        lost |= (means[:, 0] < -level[0]) | (means[:, 1] < -level[1])
    return chosen_somewhere & ~lost, lost


def keep_probability(rule: Rule, noises: dict[str, Noise], effect: float, rng: np.random.Generator
                     ) -> tuple[float, float]:
    """How often ``rule`` keeps a change whose true effect on both cameras' halves is ``effect``, and the seeds it
    runs on average; where it asks for more seeds, the change neither kept nor lost on the first is judged again on
    all."""
    seeds = max(rule.seeds, rule.more_seeds)
    differences = {camera: per_seed_differences(noise, effect, seeds, rng) for camera, noise in noises.items()}
    kept, lost = verdicts(rule, rule.seeds, differences, noises)
    if not rule.more_seeds:
        return float(np.mean(kept)), float(rule.seeds)
    undecided = ~kept & ~lost
    kept_later, _ = verdicts(rule, rule.more_seeds, differences, noises)
    return float(np.mean(kept | undecided & kept_later)), rule.seeds + (rule.more_seeds - rule.seeds) * float(
        np.mean(undecided))


def levels(noises: dict[str, Noise], seeds: int) -> str:
    scale = 2 / np.sqrt(seeds)
    return ", ".join(f"{camera} ±{scale * noise.choosing:.3f} / ±{scale * noise.confirming:.3f}"
                     for camera, noise in noises.items())


def main() -> None:
    spread = json.loads((RESULTS / "spread.json").read_text())
    kinds = {"retrained": retraining_noise(spread)}
    pairs_path = RESULTS / "decode_noise.json"
    if pairs_path.exists():
        kinds["read another way"] = {camera: Noise(**value)
                                     for camera, value in json.loads(pairs_path.read_text()).items()}
    rng = np.random.default_rng(0)
    table = {kind: {rule.name: [keep_probability(rule, noises, effect, rng) for effect in EFFECTS] for rule in RULES}
             for kind, noises in kinds.items()}
    shown = [-0.02, -0.01, -0.005, 0.0, 0.005, 0.01, 0.02]
    lines = [f"# How often a rule keeps a change of known effect ({FIGURE}, the same effect on both cameras' halves)",
             ""]
    for kind, noises in kinds.items():
        lines += [f"## A change {kind}", "",
                  "Per-seed difference SD (choosing / confirming; correlation of the halves): "
                  + ", ".join(f"{camera} {n.choosing:.3f} / {n.confirming:.3f} ({n.correlation:+.2f})"
                              for camera, n in noises.items()), "",
                  f"Two standard errors: three seeds {levels(noises, 3)}; six seeds {levels(noises, 6)}", "",
                  "Each cell: the probability the rule keeps a change of that true effect (the seeds it runs on "
                  "average, each arm and camera).", "",
                  "| rule | " + " | ".join(f"{effect:+.3f}" for effect in shown) + " |",
                  "|---|" + "---|" * len(shown)]
        for name, probabilities in table[kind].items():
            picked = [probabilities[int(np.argmin(np.abs(EFFECTS - effect)))] for effect in shown]
            lines.append(f"| {name} | " + " | ".join(f"{p:.2f} ({n:.1f})" for p, n in picked) + " |")
        lines.append("")
    (RESULTS / "rules.md").write_text("\n".join(lines))
    print("\n".join(lines))

    figure, axes = plt.subplots(1, len(kinds), figsize=(6 * len(kinds), 4.2), squeeze=False)
    for axis, (kind, rows) in zip(axes[0], table.items(), strict=True):
        for name, probabilities in rows.items():
            axis.plot(EFFECTS, [p for p, _ in probabilities], marker=".", label=name)
        axis.axvline(0, color="grey", lw=0.8)
        axis.set(title=f"a change {kind}", xlabel=f"true effect on {FIGURE} (both cameras, both halves)",
                 ylabel="probability the rule keeps it", ylim=(0, 1))
        axis.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8, loc="upper left")
    figure.tight_layout()
    figure.savefig(RESULTS / "keep_probability.png", dpi=110)


if __name__ == "__main__":
    main()
