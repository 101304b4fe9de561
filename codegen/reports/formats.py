"""The report formats by name (--format), each a writer of a list of cell results."""

from __future__ import annotations

from pathlib import Path

from codegen.reports.findings import CellResult
from codegen.reports.github import github
from codegen.reports.junit import junit
from codegen.reports.sarif import sarif

WRITERS = {
    "junit": lambda results, root: junit(results),
    "sarif": sarif,
    "github": github,
}
FORMATS = ("text", "json", *WRITERS)  # text and json: each command's own


def write(name: str, results: list[CellResult], root: Path) -> str:
    return WRITERS[name](results, root)
