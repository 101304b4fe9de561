"""Writing what users keep: a cell's output folder replaced whole (staged beside it, switched by one atomic
exchange, under a lock) and the files of an output folder replaced in one step."""

from __future__ import annotations

import ctypes
import os
import re
import secrets
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
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
except ImportError:  # not POSIX: no lock (documented in docs/generate.md)
    fcntl = None

STAGE = ".{cell}.codegen-new-{token}"  # the new set being written (or, after the exchange, the old set)
ASIDE = ".{cell}.codegen-old-{token}"  # without an atomic exchange: the old set while the new one moves in
LOCK = ".{cell}.lock"  # held while a process writes the cell's folder; its journal (never removed: see _lock)
JOURNAL = "codegen's lock and journal of this cell's output folder; keep it (git ignores it)\n"
JOURNAL_MAX = 4096  # bytes of a journal: two names
_AT_FDCWD = -100
_RENAME_NOREPLACE = 1  # renameat2(2) flags: fail if the new name exists; swap two paths atomically
_RENAME_EXCHANGE = 2  # (Linux 3.15+, glibc 2.28+)


class OutputBusy(Exception):
    """Another process is writing the same cell's output folder."""


class OutputInTheWay(Exception):
    """Something of the user's stands where codegen writes (a file or symlink as the cell's folder, a lock file
    that is not codegen's): nothing was written."""


def replace_cell(out_dir: Path, cell: str, files: dict[str, str], targets: list[str]) -> tuple[list[Path], list[str]]:
    """Make `out_dir/cell` hold `files` (path below the cell folder -> text) for `targets`, and keep
    what the folder held for its other targets and besides. The new folder is written in full beside
    the old one and switched in by one atomic exchange, so a kill at any moment leaves the complete
    old set or the complete new set under `out_dir/cell`, never a mix. The staging folders' names are
    recorded in the lock file before they are made: a later run removes or renames only what a journal
    names, never a folder of the user's that looks like one. Returns the written paths and what was left
    alone (files codegen did not write, symlinks not followed)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    final = out_dir / cell
    with _lock(out_dir, cell) as journal:
        _recover(out_dir, cell, journal)
        _refuse_in_the_way(final)
        token = f"{os.getpid()}-{secrets.token_hex(4)}"
        stage, aside = (out_dir / name.format(cell=cell, token=token) for name in (STAGE, ASIDE))
        journal.record([("stage", stage.name), ("aside", aside.name)])
        try:
            stage.mkdir()
            left_alone = _carry_over(final, stage, targets, set(files)) if final.is_dir() else []
            for relpath, text in files.items():
                _write(stage / relpath, text)
            _sync_dir(stage)
            _switch(stage, final, aside)
        finally:
            _recover(out_dir, cell, journal)  # the old set after the exchange, or a new set never switched in
        _sync_dir(out_dir)
    return [final / relpath for relpath in files], left_alone


def _refuse_in_the_way(final: Path) -> None:
    """The cell's folder must be a folder or nothing: a file or a symlink there is the user's (the exchange
    would move it aside, a symlink would be replaced by a folder); it stays, and nothing is written."""
    if final.is_symlink():
        raise OutputInTheWay(
            f"{final}: a symlink (to {os.readlink(final)}); codegen replaces the cell's folder whole and does not "
            "follow it: nothing was written (give --out the folder the link is in, or remove the link)"
        )
    if final.exists() and not final.is_dir():
        raise OutputInTheWay(
            f"{final}: a file, where the cell's output folder goes; nothing was written (move it away or give "
            "another --out)"
        )


class _Journal:
    """The lock file's text: a header, then the staging folders a run is about to make ("stage NAME", "aside
    NAME"), written and flushed before they exist and cleared when the run has tidied them."""

    def __init__(self, fd: int, path: Path, cell: str):
        self.fd, self.path, self.cell = fd, path, cell

    def entries(self) -> list[tuple[str, str]]:
        """The recorded (role, name) pairs that are names codegen makes for this cell (anything else is ignored);
        OutputInTheWay when the file is not codegen's journal."""
        os.lseek(self.fd, 0, os.SEEK_SET)
        text = os.read(self.fd, JOURNAL_MAX + 1).decode("utf-8", "replace")
        if text and not text.startswith(JOURNAL):
            raise OutputInTheWay(
                f"{self.path}: not codegen's lock file (codegen keeps its lock and journal there); nothing was "
                "written (move it away)"
            )
        names = {role: _name_pattern(pattern, self.cell) for role, pattern in (("stage", STAGE), ("aside", ASIDE))}
        found = []
        for line in text[len(JOURNAL) :].splitlines():
            role, _, name = line.partition(" ")
            if role in names and names[role].fullmatch(name):
                found.append((role, name))
        return found

    def record(self, entries: list[tuple[str, str]]) -> None:
        text = JOURNAL + "".join(f"{role} {name}\n" for role, name in entries)
        os.lseek(self.fd, 0, os.SEEK_SET)
        os.write(self.fd, text.encode("utf-8"))
        os.ftruncate(self.fd, len(text.encode("utf-8")))
        os.fsync(self.fd)


def _name_pattern(name: str, cell: str) -> re.Pattern:
    """A staging name of the cell's, whatever its token (the pid and 8 hex digits)."""
    return re.compile(re.escape(name.format(cell=cell, token="@")).replace("@", "[0-9]+-[0-9a-f]{8}"))


@contextmanager
def _lock(out_dir: Path, cell: str) -> Iterator[_Journal]:
    """An exclusive lock per cell folder, released by the kernel when the process dies, on the file that holds
    the journal. The lock file stays: removing it would let a process that opened it just before hold a lock
    nobody else sees. A symlink or a folder in its place is refused (never followed, never written through)."""
    path = out_dir / LOCK.format(cell=cell)
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o666)
    except OSError as exc:
        if not path.is_symlink() and not path.is_dir():
            raise
        raise OutputInTheWay(
            f"{path}: a {'symlink' if path.is_symlink() else 'folder'} where codegen keeps its lock file; nothing "
            "was written (move it away)"
        ) from exc
    try:
        if fcntl is not None:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                raise OutputBusy(
                    f"{out_dir / cell}: another codegen generate is writing this cell's programs; "
                    "nothing was written (run again when it has finished)"
                ) from None
        yield _Journal(fd, path, cell)
    finally:
        os.close(fd)


def _recover(out_dir: Path, cell: str, journal: _Journal) -> None:
    """Tidy what a killed run left, as its journal names it: a set moved aside comes back if the cell folder
    is missing (the kill fell between the two renames of the fallback); the other staged folders are deleted.
    Folders the journal does not name are never touched, whatever their names."""
    final = out_dir / cell
    entries = journal.entries()
    for role, name in sorted(entries, key=lambda entry: entry[0] != "aside"):
        path = out_dir / name
        if not path.is_dir() or path.is_symlink():
            continue
        if role == "aside" and not final.exists() and not final.is_symlink():
            os.rename(path, final)
        else:
            shutil.rmtree(path)
    if entries:
        journal.record([])


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
    otherwise two renames (a kill between them is repaired by _recover on the next run). Where the cell's
    folder is missing, a rename that never replaces what another process made there meanwhile."""
    if not final.exists() and not final.is_symlink():
        if not _renameat2(stage, final, _RENAME_NOREPLACE):
            os.rename(stage, final)
    elif not _exchange(stage, final):
        os.rename(final, aside)
        os.rename(stage, final)
        shutil.rmtree(aside)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically; False where the system cannot."""
    return _renameat2(a, b, _RENAME_EXCHANGE)


def _renameat2(a: Path, b: Path, flags: int) -> bool:
    """renameat2(2) with `flags` (swap two paths, or no replacing); False where the system cannot."""
    renameat2 = getattr(_libc(), "renameat2", None)
    if renameat2 is None:
        return False
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), flags) == 0:
        return True
    error = ctypes.get_errno()
    if error in (22, 38, 95):  # EINVAL, ENOSYS, EOPNOTSUPP: not on this system or filesystem
        return False
    raise OSError(error, os.strerror(error), str(b))


def _libc():
    try:
        return ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None


def write_file(path: Path, text: str) -> None:
    """A file of an output folder written in one step: beside it, flushed, then renamed into place, so a kill
    leaves the old file or the new one; a symlink in its place is replaced, never written through (what it
    names is not touched). The permissions a normal write gives (the umask applies)."""
    temporary = path.parent / f".{path.name}.{secrets.token_hex(4)}.tmp"
    try:
        _write(temporary, text)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
