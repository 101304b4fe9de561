"""Which files make the program an edited file belongs to, read from disk where the editor does not hold them."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from codegen.dialects import Dialect, dialect_of_suffix
from codegen.dialects.core.files import SourceFile, read_source
from codegen.dialects.core.values import RunError

CELL_SUFFIX = ".toml"
CELL_TABLE = re.compile(r"^\s*\[\s*cell\s*[\].]", re.MULTILINE)
NOT_CELLS = frozenset({"pyproject.toml", "codegen.toml"})  # TOML files of a project and a plant, not cells


@dataclass(frozen=True)
class Program:
    """The files of one program (the program file first; the file asked about among them), its language, and an
    error that keeps the files from making a program (RunError text), if any."""

    dialect: type[Dialect]
    files: tuple[SourceFile, ...]
    error: str = ""

    def text_of(self, path: str) -> str | None:
        return next((f.text for f in self.files if f.name == path), None)


def is_cell_file(path: Path) -> bool:
    return path.suffix.lower() == CELL_SUFFIX and path.name.lower() not in NOT_CELLS


def is_cell_text(text: str) -> bool:
    """Whether a TOML text is a cell file's: it has a [cell] table (another TOML file, a controller's facts or a
    catalogue, gets no cell diagnostics)."""
    return CELL_TABLE.search(text) is not None


def dialect_of(path: Path) -> type[Dialect] | None:
    return dialect_of_suffix(path.suffix)


def program_of(path: Path, open_texts: dict[str, str]) -> Program | None:
    """The program `path` is part of: the files of its language in its folder as the language groups them
    (Dialect.programs: a .src with its .dat and the data lists it uses, a RAPID task's modules), each file's text
    the editor's where it holds the file (open_texts: path -> text), else the disk's. None: not a program file."""
    dialect = dialect_of(path)
    if dialect is None:
        return None
    own = dialect.suffixes + dialect.companions + dialect.configurations  # a channel's configuration: EKI_Init reads it
    folder = path.parent
    found = sorted(folder.iterdir()) if folder.is_dir() else []
    paths = {str(p): p for p in found if p.is_file() and p.suffix.lower() in own}
    paths.setdefault(str(path), path)
    paths.update({k: Path(k) for k in open_texts if Path(k).parent == folder and Path(k).suffix.lower() in own})
    files = []
    for name, p in paths.items():
        if name in open_texts:
            files.append(SourceFile(name, open_texts[name]))
            continue
        try:
            files.append(read_source(p, dialect.encodings))
        except RunError:
            continue  # a file beside it that cannot be read is not this file's concern
    mine = next((f for f in files if f.name == str(path)), None)
    if mine is None:  # neither open nor readable
        return None
    try:
        groups = dialect.programs(files)
    except RunError as exc:
        return Program(dialect, (mine,), str(exc))
    group = next((g for g in groups if any(f.name == mine.name for f in g)), None)
    if group is None:  # a data file no program of the folder reads: checked alone
        return Program(dialect, (mine,))
    return Program(dialect, tuple(group))
