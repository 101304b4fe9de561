"""Reading a file the user gives: a regular file only (a pipe or a device would block), at most a bound of bytes."""

from __future__ import annotations

import os
import stat
from pathlib import Path


class ReadError(ValueError):
    """A file that cannot be read as asked; the message names the file."""


def read_regular(path: Path, limit: int, what: str, bound: str, reading: str = "cannot read") -> bytes:
    """The bytes of a regular file of at most `limit` bytes; otherwise a ReadError naming the file: `what` it
    should be (a folder, a FIFO, a device), why the bound (too large), `reading` and the system's reason
    (unreadable). Opened without blocking, so a FIFO is refused at once instead of waiting for a writer."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except OSError as exc:
        raise ReadError(f"{path}: {reading}: {exc.strerror or exc}") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise ReadError(f"{path}: not a regular file (a folder, pipe or device); give {what}")
        with os.fdopen(fd, "rb", closefd=False) as handle:
            data = handle.read(limit + 1)
    except OSError as exc:
        raise ReadError(f"{path}: {reading}: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    if len(data) > limit:
        raise ReadError(f"{path}: larger than {limit >> 20} MiB; {bound}")
    return data
