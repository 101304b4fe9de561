"""Diagnostics: `codegen check`'s findings of a program's files, a cell file's load errors, at their ranges."""

from __future__ import annotations

import inspect
import re
import tomllib
from pathlib import Path

from lsprotocol import types

from codegen.dialects import Dialect
from codegen.dialects.core.files import CheckOptions, Finding, finding_of
from codegen.dialects.core.values import RunError
from codegen.lsp.documents import Program
from codegen.model.lines import line_of
from codegen.model.validate import CellError

SOURCE = "codegen"
SEVERITY = {
    "error": types.DiagnosticSeverity.Error,
    "unsupported": types.DiagnosticSeverity.Error,
    "warning": types.DiagnosticSeverity.Warning,
}
WORD = re.compile(r"[$\w]+|\S")  # a finding's range: the name (or the one character) it names, to the line's end
TOML_PLACE = re.compile(r"\(at line (\d+), column (\d+)\)")


def word_range(text: str, line: int, column: int) -> types.Range:
    """The range of a place given 1-based (column 0: the whole line; line 0: the first line): the word that
    starts there, or the line's text."""
    lines = text.split("\n")
    row = min(max(line, 1), max(len(lines), 1)) - 1
    content = lines[row] if row < len(lines) else ""
    if column <= 0 or column > len(content.rstrip()):  # the whole line; past its end (a missing bracket) too
        start = len(content) - len(content.lstrip())
        return types.Range(types.Position(row, start), types.Position(row, max(len(content.rstrip()), start)))
    start = min(column - 1, len(content))
    match = WORD.match(content, start)
    end = match.end() if match else len(content)
    return types.Range(types.Position(row, start), types.Position(row, max(end, start)))


def diagnostic(text: str, finding: Finding) -> types.Diagnostic:
    return types.Diagnostic(
        range=word_range(text, finding.line, finding.column),
        message=finding.message,
        severity=SEVERITY.get(finding.severity, types.DiagnosticSeverity.Error),
        code=finding.code,
        source=SOURCE,
    )


def syntax_findings(dialect: type[Dialect], path: str, text: str) -> list[Finding]:
    """The syntax errors of one file: what is shown while the whole program's check is still coming."""
    try:
        dialect.check(text, path)
    except RunError as exc:
        return [finding_of(exc, [path], "syntax")]
    except RecursionError:
        return [Finding(path, 0, 0, "error", "syntax", "statements or expressions nested too deeply")]
    return []


def program_findings(program: Program) -> list[Finding]:
    """Every finding of `codegen check` in the program's files (Dialect.check_files)."""
    if program.error:
        return [finding_of(program.error, list(program.files), "files")]
    check = program.dialect.check_files
    files = list(program.files)
    try:
        if "options" in inspect.signature(check).parameters:
            return check(files, options=CheckOptions())
        return check(files)
    except RecursionError:
        return [Finding(files[0].name, 0, 0, "error", "syntax", "statements or expressions nested too deeply")]


def by_file(program: Program, findings: list[Finding]) -> dict[str, list[types.Diagnostic]]:
    """The findings as diagnostics per file of the program (every file present, a clean one with none); a finding
    naming a file by another spelling (its name alone) is matched by its name."""
    out: dict[str, list[types.Diagnostic]] = {f.name: [] for f in program.files}
    names = {Path(f.name).name: f.name for f in program.files}
    for finding in findings:
        file = finding.file if finding.file in out else names.get(Path(finding.file).name, program.files[0].name)
        out[file].append(diagnostic(program.text_of(file) or "", finding))
    return out


def cell_diagnostics(text: str, path: str) -> list[types.Diagnostic]:
    """A cell file's load error at its key's line and column (or the TOML syntax error's place); none when it
    loads. The cell's warnings at the line of the key they name, where they name one."""
    from codegen.model.cell import cell_from_dict

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        place = TOML_PLACE.search(str(exc))
        line, column = (int(place[1]), int(place[2])) if place else (1, 0)
        return [_cell_diagnostic(text, line, column, f"TOML syntax error: {exc}", "toml")]
    except (RecursionError, ValueError) as exc:
        return [_cell_diagnostic(text, 1, 0, f"cannot read: {exc}", "toml")]
    try:
        cell = cell_from_dict(data, source=path)
    except CellError as exc:
        line = line_of(text, exc.key) if exc.key else None
        column = _key_column(text, line, exc.key) if line else 0
        message = f"{exc.key}: {exc.detail}" if exc.key else str(exc)
        return [_cell_diagnostic(text, line or 1, column, message, "cell")]
    except RecursionError:
        return [_cell_diagnostic(text, 1, 0, "tables or arrays nested too deeply", "cell")]
    return [_cell_warning(text, path, warning) for warning in cell.warnings]


def _cell_warning(text: str, path: str, warning: str) -> types.Diagnostic:
    """A cell's warning ("file: key path: message") at its key, where the text writes the key."""
    said = warning.removeprefix(f"{path}: ")
    key, _, message = said.partition(": ")
    line = line_of(text, key) if message else None
    column = _key_column(text, line, key) if line else 0
    return _cell_diagnostic(text, line or 1, column, said, "cell-warning", warning=True)


def _key_column(text: str, line: int, key: str) -> int:
    """The 1-based column of the key path's last name on its line (0: not written there)."""
    name = re.split(r"[.\[\]]", key.rstrip("]"))[-1] if key else ""
    content = text.split("\n")[line - 1]
    found = re.search(rf"(?<![\w-]){re.escape(name)}(?![\w-])", content) if name else None
    return found.start() + 1 if found else 0


def _cell_diagnostic(text: str, line: int, column: int, message: str, code: str, warning=False) -> types.Diagnostic:
    return types.Diagnostic(
        range=word_range(text, line, column),
        message=message,
        severity=types.DiagnosticSeverity.Warning if warning else types.DiagnosticSeverity.Error,
        code=code,
        source=SOURCE,
    )
