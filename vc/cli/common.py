"""What every command shares: the bad-input contract (one line, exit status 2) and logging set-up."""

from __future__ import annotations

import functools
import logging
import sys
from collections.abc import Callable

from vc.errors import EXIT_BAD_INPUT, InputError


def handles_input_errors(main: Callable[[list[str] | None], int]) -> Callable[[list[str] | None], int]:
    """Turn an :class:`InputError` escaping ``main`` into one ``error:`` line on stderr and exit status 2."""

    @functools.wraps(main)
    def wrapper(argv: list[str] | None = None) -> int:
        logging.basicConfig(level=logging.INFO, format="%(message)s")
        try:
            return main(argv)
        except InputError as error:
            print(f"error: {error}", file=sys.stderr)
            return EXIT_BAD_INPUT
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            return 130

    return wrapper
