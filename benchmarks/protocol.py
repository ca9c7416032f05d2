"""The project's rule for choices measured on real frames (docs/evaluation.md#choosing-and-confirming): a setting is
chosen on the first half of the annotated frames a session can see and kept only if it holds on the second half,
which played no part in choosing it. So a benchmark that scores real frames reports both halves beside the whole, and
a change is called a gain or a loss only beyond what its seeds' spread alone would give."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

from vc.deploy.frames import FrameRange

CHOOSING, CONFIRMING = "choosing", "confirming"
HALVES = (CHOOSING, CONFIRMING)


def middle(first: int, last: int) -> int:
    """The last frame of the choosing half of frames ``first`` to ``last``: PETS09's dev frames 1-400 split at 200,
    TUD-Stadtmitte's 1-179 at 90."""
    return (first + last) // 2


def frame_halves(frames: FrameRange, last: int) -> dict[str, FrameRange]:
    """``frames`` (its ``last`` None: up to ``last``, the last annotated frame) as its two halves, each keeping the
    step: 1:400:5 is 1:200:5 and 201:400:5."""
    end = last if frames.last is None else frames.last
    split = middle(frames.first, end)
    second = frames.first + ((split - frames.first) // frames.step + 1) * frames.step
    return {CHOOSING: FrameRange(frames.first, split, frames.step), CONFIRMING: FrameRange(second, end, frames.step)}


def positions_by_half(numbers: Sequence[int], first: int, last: int) -> dict[str, list[int]]:
    """The positions in ``numbers`` (the frame numbers scored, from a selection of ``first`` to ``last``) of each
    half's frames."""
    split = middle(first, last)
    return {CHOOSING: [k for k, number in enumerate(numbers) if number <= split],
            CONFIRMING: [k for k, number in enumerate(numbers) if number > split]}


def halves_cell(point: dict, field: str = "real_ap50") -> str:
    """A report's table cell: ``point``'s ``field`` on the choosing and the confirming half (``FIELD_choosing``,
    ``FIELD_confirming``), or a dash where it was measured before the halves were."""
    values = [point.get(f"{field}_{half}") for half in HALVES]
    return " / ".join(f"{value:.3f}" for value in values) if None not in values else "—"


class Change(StrEnum):
    """What a change draws again, which decides how far its per-seed difference moves by chance alone."""

    READ = "read"  # the same bundles read another way: decoding, tracking, the runtime's rules
    RETRAINED = "retrained"  # networks trained again, on the same renders or on new ones


# One seed's difference from what a change replaces: its standard deviation from seed to seed, choosing and
# confirming half, by change, figure and camera. Read: pooled over earlier experiments' variants; retrained: two
# compiles' spread, measured on nine compiles a camera
# (decisions/0056-a-level-band-from-the-seeds-spread.md).
SEED_SPREAD: dict[tuple[Change, str, str], tuple[float, float]] = {
    (Change.READ, "AP50 tracked", "pets"): (0.0033, 0.0027),
    (Change.READ, "AP50 tracked", "tud"): (0.0100, 0.0081),
    (Change.READ, "AP50 each frame", "pets"): (0.0042, 0.0045),
    (Change.READ, "AP50 each frame", "tud"): (0.0081, 0.0160),
    (Change.READ, "pose tracked", "pets"): (0.0028, 0.0021),
    (Change.READ, "pose tracked", "tud"): (0.0218, 0.0191),
    (Change.RETRAINED, "AP50 tracked", "pets"): (0.0184, 0.0112),
    (Change.RETRAINED, "AP50 tracked", "tud"): (0.0245, 0.0161),
    (Change.RETRAINED, "AP50 each frame", "pets"): (0.0191, 0.0111),
    (Change.RETRAINED, "AP50 each frame", "tud"): (0.0151, 0.0060),
    (Change.RETRAINED, "pose each frame", "pets"): (0.0417, 0.0207),
    (Change.RETRAINED, "pose each frame", "tud"): (0.0580, 0.0656),
    (Change.RETRAINED, "pose tracked", "pets"): (0.0147, 0.0181),
    (Change.RETRAINED, "pose tracked", "tud"): (0.0883, 0.0825),
}


@dataclass(frozen=True)
class Difference:
    """A change's mean difference over its seeds on one camera's half, and the band within which it is level: twice
    the standard error of that mean, so a change that does nothing is called a gain about one time in 40."""

    camera: str
    half: str
    mean: float
    level_within: float

    @property
    def call(self) -> str:
        return "gain" if self.mean > self.level_within else "loss" if self.mean < -self.level_within else "level"


def difference(change: Change, figure: str, camera: str, half: str, replaced: Sequence[float],
               changed: Sequence[float]) -> Difference:
    """``changed`` against ``replaced``, each a figure per seed in the same seed order."""
    if len(replaced) != len(changed) or not replaced:
        raise ValueError(f"{figure} on {camera}'s {half} half: {len(replaced)} seeds replaced, {len(changed)} changed; "
                         "a change is compared seed by seed")
    try:
        spread = SEED_SPREAD[change, figure, camera][HALVES.index(half)]
    except KeyError:
        raise ValueError(f"no measured seed-to-seed spread of {figure} on {camera} for a {change} change; measured: "
                         f"{sorted({key[1] for key in SEED_SPREAD if key[0] == change})}") from None
    mean = sum(b - a for a, b in zip(replaced, changed, strict=True)) / len(changed)
    return Difference(camera, half, mean, 2 * spread / math.sqrt(len(changed)))


def kept(differences: Sequence[Difference]) -> bool:
    """The rule (docs/evaluation.md#choosing-and-confirming): a gain on at least one camera's choosing half, a loss
    on no half of either camera."""
    calls = [(d.half, d.call) for d in differences]
    return (CHOOSING, "gain") in calls and all(call != "loss" for _, call in calls)
