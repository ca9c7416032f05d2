"""What every command shares: the bad-input contract (one line, exit status 2), logging set-up and argument
types."""

from __future__ import annotations

import argparse
import functools
import logging
import sys
from collections.abc import Callable

from vc.errors import EXIT_BAD_INPUT, EXIT_STAGE_FAILED, NO_ROOM, InputError, OutputError, StageError


def handles_input_errors(main: Callable[[list[str] | None], int]) -> Callable[[list[str] | None], int]:
    """Turn an :class:`InputError` escaping ``main`` into one ``error:`` line on stderr and exit status 2, a
    :class:`StageError` (an :class:`OutputError` too, and an OSError that says the disk is full) into one line and
    status 1."""

    @functools.wraps(main)
    def wrapper(argv: list[str] | None = None) -> int:
        logging.basicConfig(level=logging.INFO, format="%(message)s")
        try:
            return main(argv)
        except InputError as error:
            print(f"error: {error}", file=sys.stderr)
            return EXIT_BAD_INPUT
        except StageError as error:
            print(f"error: {error}", file=sys.stderr)
            return EXIT_STAGE_FAILED
        except OSError as error:
            if error.errno not in NO_ROOM:
                raise
            print(f"error: {OutputError(error.filename or 'an output', error.strerror)}", file=sys.stderr)
            return EXIT_STAGE_FAILED
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            return 130

    return wrapper


def _whole_number(minimum: int):
    """An argparse type: a whole number of at least ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}, got {value}")
        return value

    return parse


positive_int = _whole_number(1)
non_negative_int = _whole_number(0)


def positive_float(text: str) -> float:
    """An argparse type: a finite number above zero."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (0.0 < value < float("inf")):
        raise argparse.ArgumentTypeError(f"must be a finite number above 0, got {text!r}")
    return value


def fitness_line(fitness: dict) -> str:
    """One printed line of a summary's scene fitness (:meth:`vc.deploy.runtime.Runtime.fitness_summary`): frames per
    state, and what happened to the people of the unfit ones."""
    if "unknown_because" in fitness:
        return f"  scene fitness unknown: {fitness['unknown_because']}"
    states = fitness["states"]
    counts = ", ".join(f"{count} {state}" for state, count in states.items()) or "no frames"
    corrected = [f"{fitness[key]} {what}" for key, what in (
        ("exposure_corrected_frames", "brought back from light beyond the range"),
        ("veil_taken_off_frames", "with a veil beyond the range taken off"),
        ("registered_frames", "with the view moved or turned back")) if fitness.get(key)]
    if corrected:
        counts += f" ({', '.join(corrected)})"
    if not fitness["unfit_frames"]:
        return f"  scene fitness: {counts}"
    kept = "withheld" if fitness["unfit"] == "suppress" else "kept, flagged (a covered frame's withheld)"
    return f"  scene fitness: {counts}; the people of the {fitness['unfit_frames']} unfit frame(s) {kept}"

