"""The project's rule for choices measured on real frames (docs/evaluation.md#choosing-and-confirming): a setting is
chosen on the first half of the annotated frames a session can see and kept only if it holds on the second half,
which played no part in choosing it. So a benchmark that scores real frames reports both halves beside the whole."""

from __future__ import annotations

from collections.abc import Sequence

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
