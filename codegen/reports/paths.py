"""Report paths: a file as the repository sees it (relative to its root, forward slashes), or absolute outside it."""

from __future__ import annotations

from pathlib import Path


def repository_root(start: Path | None = None) -> Path:
    """The folder holding .git at or above start (default: the current folder), else start itself."""
    here = (start or Path.cwd()).resolve()
    return next((p for p in (here, *here.parents) if (p / ".git").exists()), here)


def relative(file: str, root: Path) -> str | None:
    """file relative to root (posix), or None where it lies outside root (or is no real path, e.g. <fresh>/...)."""
    if file.startswith("<"):
        return None
    try:
        return Path(file).resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return None
