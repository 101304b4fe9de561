"""The cell a generated program was generated from: named by the client, else found in the workspace by name."""

from __future__ import annotations

import tomllib
from pathlib import Path

SKIPPED = frozenset({".git", "node_modules", ".venv", "venv", "__pycache__", "site", ".tox"})
MAX_FILES = 2000  # TOML files looked at in a workspace before giving up


def cell_names(program: Path) -> set[str]:
    """The cell names a generated program's place suggests: generated/<cell>/<target>/<file> and the file's stem."""
    return {program.parent.parent.name, program.stem}


def find_cell(program: Path, roots: list[Path]) -> Path | None:
    """The cell file under the roots (or above the program) whose [cell] name is the program's cell's."""
    wanted = cell_names(program)
    seen = 0
    for root in [*roots, *program.parents]:
        for path in _tomls(root):
            seen += 1
            if seen > MAX_FILES:
                return None
            try:
                name = tomllib.loads(path.read_text(encoding="utf-8")).get("cell", {}).get("name")
            except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, AttributeError):
                continue
            if name in wanted:
                return path
        if roots:
            break  # the workspace was searched; the program's own folders only without one
    return None


def _tomls(root: Path):
    if not root.is_dir():
        return
    stack = [root]
    while stack:
        folder = stack.pop()
        try:
            entries = sorted(folder.iterdir())
        except OSError:
            continue
        for entry in entries:
            if entry.is_dir() and entry.name not in SKIPPED and not entry.is_symlink():
                stack.append(entry)
            elif entry.suffix == ".toml" and entry.is_file():
                yield entry
