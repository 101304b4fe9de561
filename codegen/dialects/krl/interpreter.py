"""KRL interpreter: parse, load and check programs of one or several files (the compiler: compiler.py)."""

from __future__ import annotations

from pathlib import Path

from codegen.dialects.core.files import read_source
from codegen.dialects.core.program import Program
from codegen.dialects.krl.compiler import KRLCompiler
from codegen.dialects.krl.modules import load, load_files, programs
from codegen.dialects.krl.syntax import parse

ENCODINGS = ("cp1252",)  # KUKA controllers write their files in Windows-1252 (backups, WorkVisual projects)

__all__ = ["ENCODINGS", "KRLCompiler", "load", "load_file", "load_files", "parse", "programs"]


def load_file(path: Path) -> Program:
    """A .src with the .dat beside it, read in the controller's encodings."""
    files = [read_source(path, ENCODINGS)]
    dat = path.with_suffix(".dat")
    if dat.exists():
        files.append(read_source(dat, ENCODINGS))
    return load_files(files)
