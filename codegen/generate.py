"""`codegen generate` and `codegen diff`: render every target, check, then write or compare."""

from __future__ import annotations

import difflib
from pathlib import Path

from codegen.cell import Cell
from codegen.render import RenderedFile, cell_dir, render, write_atomic


class GenerateError(Exception):
    """Rendered output that fails a check; nothing has been written."""


def check_rendered(files: list[RenderedFile]) -> None:
    """Checks every program passes before any file is replaced."""
    for f in files:
        if not f.text.isascii():
            raise GenerateError(f"{f.relpath}: non-ASCII output")
        if not f.text.endswith("\n"):
            raise GenerateError(f"{f.relpath}: no final newline")
        from codegen.dialects import parse_program  # lark: loaded only when generating

        try:
            parse_program(f.relpath, f.text, positions=False)
        except Exception as exc:  # a generator bug, reported with the file and position
            raise GenerateError(f"{f.relpath}: generated program does not parse: {exc}") from exc


def generate(cell: Cell, targets: list[str] | None, out_dir: Path) -> list[Path]:
    files = render(cell, targets)
    check_rendered(files)
    written = write_atomic(files, out_dir)
    # Remove files a previous run wrote for these targets that this run did not produce.
    produced = {out_dir / f.relpath for f in files}
    for target in targets or cell.targets:
        folder = out_dir / cell_dir(cell) / target
        for stale in sorted(folder.glob("*")):
            if stale.is_file() and stale not in produced:
                stale.unlink()
    return written


def diff(cell: Cell, out_dir: Path) -> str:
    """Unified diff from the files in out_dir to fresh output ('' when identical)."""
    files = render(cell)
    chunks = []
    produced = set()
    for f in files:
        path = out_dir / f.relpath
        produced.add(path)
        old = path.read_text(encoding="utf-8") if path.exists() else ""
        if old != f.text:
            chunks.extend(
                difflib.unified_diff(
                    old.splitlines(keepends=True),
                    f.text.splitlines(keepends=True),
                    fromfile=str(path) if path.exists() else "/dev/null",
                    tofile=f"{path} (fresh)",
                )
            )
    for target in cell.targets:
        folder = out_dir / cell_dir(cell) / target
        for extra in sorted(folder.glob("*")):
            if extra.is_file() and extra not in produced:
                chunks.append(f"Only in {folder}: {extra.name} (not generated any more)\n")
    return "".join(chunks)
