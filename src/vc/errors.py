"""The one error type for bad user input: it names the file, the field and the reason.

Every command catches it at the top (``vc.cli.common``), prints one line and exits with status 2, so a user
never sees a traceback for a mistake in their own files.
"""

from __future__ import annotations

import errno
from pathlib import Path

#: Exit status for bad input (files, fields, arguments), as argparse uses for bad arguments.
EXIT_BAD_INPUT = 2
#: Exit status for a stage that ran on good input and could not finish (training diverged).
EXIT_STAGE_FAILED = 1


class InputError(Exception):
    """Bad input: ``path`` (file or folder), ``field`` (dotted path inside it, or "" for the whole file)."""

    def __init__(self, path: str | Path | None, field: str, reason: str) -> None:
        self.path = str(path) if path is not None else None
        self.field = field
        self.reason = reason
        super().__init__(str(self))

    def __str__(self) -> str:
        parts = [p for p in (self.path, self.field) if p]
        return ": ".join(parts + [self.reason])


class StageError(Exception):
    """A stage that could not finish on good input (training diverged): one line saying what happened and what
    was kept, exit status 1."""


#: errno values that mean "no room to write": a full disk, a full quota, a file-size limit.
NO_ROOM = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})


class OutputError(StageError):
    """An output that could not be written on good input (a full disk, a quota, a file-size limit, a failing
    device). Outputs are written under temporary names and renamed into place, so everything finished before the
    failure is intact: the same command resumes once there is room."""

    def __init__(self, path: str | Path, reason: str) -> None:
        self.path = str(path)
        super().__init__(f"cannot write {path}: {reason}; everything finished before it is kept: make room and "
                         f"run the same command again to resume")
