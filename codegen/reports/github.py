"""GitHub Actions workflow commands: an annotation per finding (::error file=...,line=...,title=...::message)."""

from __future__ import annotations

from pathlib import Path

from codegen.reports.findings import CellResult
from codegen.reports.paths import relative
from codegen.reports.rules import rule

COMMAND = {"error": "error", "warning": "warning", "note": "notice"}


def data(text: str) -> str:
    """A command's message: % first, then the line breaks (the runner decodes %25, %0D, %0A)."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def prop(text: str) -> str:
    """A property's value: as a message, and the separators of properties (: and ,) too."""
    return data(text).replace(":", "%3A").replace(",", "%2C")


def github(results: list[CellResult], root: Path) -> str:
    """One line per finding; a file outside the repository, or none, gives an annotation without a place."""
    lines = []
    for result in results:
        for finding in result.findings:
            props = {}
            where = finding.program or finding.cell
            path = relative(where.file, root) if where is not None else None
            if path is not None:
                props["file"] = path
                if where.line:
                    props["line"] = str(where.line)
                if where.column:
                    props["col"] = str(where.column)
            props["title"] = f"{rule(finding.rule).id}" + (f" ({result.cell})" if result.cell else "")
            message = finding.message
            if finding.cell is not None and finding.cell is not where:
                message += f" [cell file {finding.cell.file}:{finding.cell.line}: {finding.key}]"
            shown = ",".join(f"{k}={prop(v)}" for k, v in props.items())
            lines.append(f"::{COMMAND[finding.level]} {shown}::{data(message)}")
    return "".join(line + "\n" for line in lines)
