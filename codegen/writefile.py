"""Writing a file the user names (a page, the schema, a calibrated cell): checked first, then replaced whole."""

from __future__ import annotations

import errno
import os
import secrets
import stat
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: no lock (two calibrations at once are then the user's to avoid)
    fcntl = None

MARK_BYTES = 2048  # codegen's mark is in a file's first lines


class WriteRefused(Exception):
    """A file cannot take what codegen would write there; the message names it and says why. Nothing was written."""


def check_own(path: Path, marks: tuple[bytes, ...]) -> Path:
    """The file a write to `path` replaces or makes (a symlink's target, which is kept as a link), if it may:
    nothing there yet, or a regular file whose first lines hold one of `marks` (a file codegen wrote). Everything
    else is refused with its reason: a folder, a FIFO, a device or a socket (writing would block or reach
    hardware), a file of the user's, a read-only file or folder, a name too long, a symlink to nothing."""
    try:
        shown = os.lstat(path)
    except FileNotFoundError:
        return _new_file(path)
    except OSError as exc:
        raise WriteRefused(f"{path}: {_reason(exc)}; nothing was written") from None
    real = Path(os.path.realpath(path)) if stat.S_ISLNK(shown.st_mode) else path
    try:
        mode = os.stat(real).st_mode
    except OSError as exc:
        raise WriteRefused(f"{path}: a symlink to {os.readlink(path)}, which {_reason(exc)}; nothing written") from None
    link = f" (a symlink to {real})" if real != path else ""
    if stat.S_ISDIR(mode):
        raise WriteRefused(f"{path}{link}: is a folder; give a file name")
    if not stat.S_ISREG(mode):
        raise WriteRefused(
            f"{path}{link}: not a regular file (a FIFO, device or socket); codegen writes regular files only: "
            "nothing was written"
        )
    if marks and not _marked(real, marks):
        raise WriteRefused(
            f"{path}{link}: exists and was not written by codegen; left alone (choose another file name)"
        )
    if not os.access(real, os.W_OK) or not mode & 0o222:  # no write bit: read-only even to root, as to an editor
        raise WriteRefused(f"{path}{link}: read-only; left as it was")
    return _writable_folder(real)


def _new_file(path: Path) -> Path:
    """A file to be made: its folder (made where missing) must take it, and its name must fit the system's."""
    folder = path.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    try:
        limit = os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    if any(len(os.fsencode(part)) > limit for part in path.parts):
        raise WriteRefused(f"{str(path)[:80]}...: a name too long (over {limit} bytes); nothing was written")
    if not folder.is_dir():
        raise WriteRefused(f"{path}: {folder} is not a folder; nothing was written")
    return _writable_folder(path, folder)


def _writable_folder(real: Path, folder: Path | None = None) -> Path:
    folder = folder or real.parent
    if not os.access(folder, os.W_OK | os.X_OK):
        raise WriteRefused(f"{real}: its folder {folder} cannot be written (read-only or no permission)")
    return real


def _marked(real: Path, marks: tuple[bytes, ...]) -> bool:
    fd = os.open(real, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    try:
        head = os.read(fd, MARK_BYTES)
    finally:
        os.close(fd)
    return any(mark in head for mark in marks)


def _reason(exc: OSError) -> str:
    if exc.errno == errno.ENAMETOOLONG:
        return "a name too long for the system"
    return (exc.strerror or str(exc)).lower()


def write_own(path: Path, text: str, marks: tuple[bytes, ...]) -> Path:
    """Write `text` to `path` whole (check_own first; a missing folder is made): a kill leaves the old file or
    the new one. A file replaced keeps its permission bits; a new one gets those of a normal write. Returns the
    file written (a symlink's target). WriteRefused, or OSError when the system fails the write."""
    real = check_own(path, marks)
    real.parent.mkdir(parents=True, exist_ok=True)
    mode = stat.S_IMODE(os.stat(real).st_mode) if real.exists() else 0o666 & ~_umask()
    put(real, text, mode)
    return real


def put(real: Path, text: str, mode: int, owner: tuple[int, int] | None = None, accept=None) -> None:
    """The one write of a whole file: `text` into a temporary file beside `real` (a short name: any name that
    fits fits it), flushed, given `mode` (and `owner` where the system lets us), renamed over `real` once
    `accept(temporary)` returns. Whatever stops it, `real` holds the old text or the new, and no temporary file
    stays (a kill can leave `.codegen-<hex>.tmp`)."""
    temporary = real.parent / f".codegen-{secrets.token_hex(6)}.tmp"
    try:
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fchmod(handle.fileno(), mode)
            if owner is not None and owner != (os.geteuid(), os.getegid()):
                with suppress(PermissionError):  # only root may give a file away; else it is the writer's, as
                    os.fchown(handle.fileno(), *owner)  # an editor's save makes it
            os.fsync(handle.fileno())
        if accept is not None:
            accept(temporary)
        os.replace(temporary, real)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    _sync_folder(real.parent)


def replace_file(path: Path, edit: Callable[[str], str], accept: Callable[[Path], None] | None = None) -> str:
    """Replace a user's text file by `edit(its text)` in one step, under a lock beside it: the text is read under
    the lock, so two edits at once both land. A symlink is followed and stays; the file keeps its permission bits,
    its owner where the system lets us, and its line ends (CRLF stays CRLF). A file with hard links, a read-only
    file, a FIFO or a device is refused (WriteRefused): a rename would cut the links, and the others are not the
    user's to change this way. `accept(written)` may refuse the new text before it replaces the old. Returns the
    text written."""
    real = check_own(path, ())
    with cell_lock(real):
        real = check_own(path, ())
        old = os.stat(real)
        if old.st_nlink > 1:
            raise WriteRefused(
                f"{path}: has {old.st_nlink} hard links; replacing it would cut them: left as it was (edit it by hand "
                "with the values printed, or write to a copy)"
            )
        fd = os.open(real, os.O_RDONLY | os.O_NONBLOCK)
        with os.fdopen(fd, "rb") as handle:
            before = handle.read().decode("utf-8")
        crlf = "\r\n" in before
        text = edit(before.replace("\r\n", "\n") if crlf else before)
        if crlf:
            text = text.replace("\r\n", "\n").replace("\n", "\r\n")
        put(real, text, stat.S_IMODE(old.st_mode), (old.st_uid, old.st_gid), accept)
    return text


@contextmanager
def cell_lock(real: Path) -> Iterator[None]:
    """An exclusive lock on the file's folder, released by the kernel when the process dies. The folder, not a lock
    file: nothing is left beside the user's file, and the folder stays the same object while its file is renamed
    over (a lock on the file itself would stay with the old one). Other edits in that folder wait their turn."""
    if fcntl is None:
        yield
        return
    fd = os.open(real.parent, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # another calibration writing here: wait for it (it takes seconds)
        yield
    finally:
        os.close(fd)


def _sync_folder(folder: Path) -> None:
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
