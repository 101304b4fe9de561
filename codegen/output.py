"""Writing what users keep: a cell's output folder replaced whole (staged beside it, switched by one atomic
exchange, under a lock) and a user's file replaced in one step (a calibration's --write)."""

from __future__ import annotations

import ctypes
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

STAMP = re.compile(r"sha256 ([0-9a-f]{64})")  # the cell file's hash in a generated file's header


def stamp_of(text: str) -> str | None:
    """The cell file's hash a generated file names in its header (None: it names none)."""
    match = STAMP.search(text[:2000])
    return match.group(1) if match else None


def mixed_set(named_texts: list[tuple[str, str]]) -> str | None:
    """A message when the given generated files (name, text) name different cell files in their headers."""
    stamps: dict[str, list[str]] = {}
    for name, text in named_texts:
        stamp = stamp_of(text)
        if stamp:
            stamps.setdefault(stamp, []).append(name)
    if len(stamps) < 2:
        return None
    parts = "; ".join(f"sha256 {h[:12]}...: {', '.join(ns)}" for h, ns in stamps.items())
    return f"these files come from different cell files (a mixed set): {parts}"


try:
    import fcntl
except ImportError:  # not POSIX: no lock (documented in the README)
    fcntl = None

STAGE = ".{cell}.new-{pid}"  # the new set being written (or, after the exchange, the old set)
ASIDE = ".{cell}.old-{pid}"  # without an atomic exchange: the old set while the new one moves in
LOCK = ".{cell}.lock"  # held while a process writes the cell's folder (never removed: see _lock)
_AT_FDCWD = -100
_RENAME_EXCHANGE = 2  # renameat2(2) flag: swap two paths atomically (Linux 3.15+, glibc 2.28+)


class OutputBusy(Exception):
    """Another process is writing the same cell's output folder."""


def replace_cell(out_dir: Path, cell: str, files: dict[str, str], targets: list[str]) -> tuple[list[Path], list[str]]:
    """Make `out_dir/cell` hold `files` (path below the cell folder -> text) for `targets`, and keep
    what the folder held for its other targets and besides. The new folder is written in full beside
    the old one and switched in by one atomic exchange, so a kill at any moment leaves the complete
    old set or the complete new set under `out_dir/cell`, never a mix. Returns the written paths and
    what was left alone (files codegen did not write, symlinks not followed)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    final = out_dir / cell
    with _lock(out_dir, cell):
        _recover(out_dir, cell)
        stage = out_dir / STAGE.format(cell=cell, pid=os.getpid())
        try:
            stage.mkdir()
            left_alone = _carry_over(final, stage, targets, set(files)) if final.is_dir() else []
            for relpath, text in files.items():
                _write(stage / relpath, text)
            _sync_dir(stage)
            _switch(stage, final, out_dir / ASIDE.format(cell=cell, pid=os.getpid()))
        finally:
            if stage.exists() or stage.is_symlink():
                shutil.rmtree(stage)  # the old set after the exchange, or a new set never switched in
        _sync_dir(out_dir)
    return [final / relpath for relpath in files], left_alone


@contextmanager
def _lock(out_dir: Path, cell: str) -> Iterator[None]:
    """An exclusive lock per cell folder, released by the kernel when the process dies. The lock file
    stays: removing it would let a process that opened it just before hold a lock nobody else sees."""
    if fcntl is None:
        yield
        return
    fd = os.open(out_dir / LOCK.format(cell=cell), os.O_RDWR | os.O_CREAT, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise OutputBusy(
                f"{out_dir / cell}: another codegen generate is writing this cell's programs; "
                "nothing was written (run again when it has finished)"
            ) from None
        yield
    finally:
        os.close(fd)


def _recover(out_dir: Path, cell: str) -> None:
    """Tidy what a killed run left: a set moved aside comes back if the cell folder is missing (the
    kill fell between the two renames of the fallback); every other staged folder is deleted."""
    final = out_dir / cell
    asides = sorted(out_dir.glob(ASIDE.format(cell=cell, pid="*")))
    if asides and not final.exists():
        os.rename(asides.pop(), final)
    for stale in [*asides, *out_dir.glob(STAGE.format(cell=cell, pid="*"))]:
        shutil.rmtree(stale)


def _carry_over(old: Path, new: Path, targets: list[str], fresh: set[str]) -> list[str]:
    """Everything of the old folder except the files codegen wrote for the regenerated targets: other
    targets' programs, a user's own files and folders (also inside a target's folder). Symlinks are
    copied as links, never followed, so nothing outside the output tree is read or changed; a target
    folder that is a symlink is replaced by a folder of its own. Returns what was left alone."""
    left_alone = []
    for entry in sorted(old.iterdir()):
        if entry.name in targets and entry.is_symlink():
            left_alone.append(f"{entry}: a symlink, replaced by a folder; {os.readlink(entry)} was not touched")
        elif entry.name in targets and entry.is_dir():
            (new / entry.name).mkdir()
            for inner in sorted(entry.iterdir()):
                relpath = f"{entry.name}/{inner.name}"
                if relpath in fresh or (inner.is_file() and not inner.is_symlink() and written_by_codegen(inner)):
                    continue  # replaced by the new program, or a program codegen no longer writes
                _copy(inner, new / relpath)
                left_alone.append(f"{inner}: not written by codegen, kept")
        elif entry.name not in targets:
            _copy(entry, new / entry.name)
    return left_alone


def written_by_codegen(path: Path) -> bool:
    """Every generated file says so in its first lines (the header of every target's templates)."""
    with open(path, "rb") as handle:
        return b"generated by codegen" in handle.read(1024)


def _copy(src: Path, dest: Path) -> None:
    if src.is_symlink():
        os.symlink(os.readlink(src), dest)
    elif src.is_dir():
        shutil.copytree(src, dest, symlinks=True)
    else:
        shutil.copy2(src, dest)


def _write(path: Path, text: str) -> None:
    """A new file with the permissions a normal write gives (the umask applies), flushed to disk."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "x", encoding="utf-8", newline="\n") as handle:
        handle.write(text)
        handle.flush()
        os.fsync(handle.fileno())


def _sync_dir(path: Path) -> None:
    """Flush a folder's entries (and its subfolders') so that a power cut keeps the renames' order."""
    for folder in [path, *(p for p in path.rglob("*") if p.is_dir() and not p.is_symlink())]:
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _switch(stage: Path, final: Path, aside: Path) -> None:
    """The new set in, in one step: an atomic exchange of the two folders where the system has one,
    otherwise two renames (a kill between them is repaired by _recover on the next run)."""
    if not final.exists():
        os.rename(stage, final)
    elif not _exchange(stage, final):
        os.rename(final, aside)
        os.rename(stage, final)
        shutil.rmtree(aside)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths with renameat2(RENAME_EXCHANGE); False where the system cannot."""
    renameat2 = getattr(_libc(), "renameat2", None)
    if renameat2 is None:
        return False
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    error = ctypes.get_errno()
    if error in (22, 38, 95):  # EINVAL, ENOSYS, EOPNOTSUPP: no exchange on this system or filesystem
        return False
    raise OSError(error, os.strerror(error), str(b))


def _libc():
    try:
        return ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None


def replace_file(path: Path, text: str, accept: Callable[[Path], None] | None = None) -> None:
    """Replace a user's file by `text` in one step: written beside the real file (a symlink is followed and stays a
    symlink; its target is replaced), with the file's permission bits (and its owner where the system lets us),
    flushed, then renamed over it once `accept(written)` returns. Whatever stops it (accept's error, a full disk,
    a kill), the file holds the old text or the new, and a failed run leaves no temporary file behind (a kill can
    leave `.<name>.<random>.tmp` beside it). OSError when the folder cannot be written."""
    real = Path(os.path.realpath(path))
    old = os.stat(real)
    fd, temporary = tempfile.mkstemp(prefix=f".{real.name}.", suffix=".tmp", dir=real.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
            handle.flush()
            os.fchmod(handle.fileno(), stat.S_IMODE(old.st_mode))
            if (old.st_uid, old.st_gid) != (os.geteuid(), os.getegid()):
                with suppress(PermissionError):  # only root may give a file away; else it is the writer's, as
                    os.fchown(handle.fileno(), old.st_uid, old.st_gid)  # an editor's save makes it
            os.fsync(handle.fileno())
        if accept is not None:
            accept(Path(temporary))
        os.replace(temporary, real)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    _sync_one(real.parent)


def _sync_one(folder: Path) -> None:
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
