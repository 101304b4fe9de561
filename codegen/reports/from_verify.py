"""verify's report as findings: a test case per program row, a finding per shown mismatch (at the line of the move or
statement it names, and the cell file's line of the pose it comes from) and per hand-edited line."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from codegen.dialects.core.files import FRESH
from codegen.model.lines import key_lines
from codegen.reports.cell_lines import entry_of, key_under
from codegen.reports.findings import CellResult, Finding, Location, TestCase
from codegen.reports.rules import EDIT, verify_rule

LINE = re.compile(r"\bline (\d+)\)")  # "move 3 (chuck, line 216)", "output X (line 40)": the checks' own words
MOVE = re.compile(r"\bmove \d+ \(([^,()]+), line \d+\)")
EDITED = re.compile(r"^EDIT (?P<file>[^:]+):(?P<line>\d+) (?P<what>changed|added): (?P<text>.*)$")
REMOVED = re.compile(r"^EDIT (?P<file>[^:]+): removed after line (?P<line>\d+): (?P<text>.*)$")


def verify_result(report, cell_file: str | None, fresh_root: Path | None = None) -> CellResult:
    """The cell's result from verify's Report; fresh programs are placed under fresh_root (the folder `codegen
    generate` writes them to: what is committed and reviewed), else named as verify names them."""
    keys = _cell_keys(cell_file)
    out = CellResult("verify", report.cell, cell_file)
    for row in report.rows:
        files = [_placed(f, fresh_root) for f in row.files]
        edits = [_edit(line, files) for line in row.edits]
        edited = [e for e in edits if e is not None]
        effects = [line.removeprefix("EDIT effect: ") for line in row.edits if line.startswith("EDIT effect: ")]
        case = TestCase(report.cell, row.target, row.program, files, row.cases, row.seconds)
        for text, problem in zip(row.first_mismatches, row.alike, strict=True):
            alike = row.alike[problem]
            message = text + (f" (and {alike} more cases alike)" if alike else "")
            line = LINE.search(problem)
            where = Location(files[0], int(line.group(1))) if line and files else None
            cell, key = _cell_place(keys, cell_file, text, problem)
            related = tuple(e.program for e in edited)
            case.findings.append(Finding(verify_rule(problem), message, "error", where, cell, key, related))
        for edit in edited:
            said = "; ".join(effects)
            message = edit.message + (f". What it changes in the nominal runs: {said}" if said else "")
            case.findings.append(Finding(edit.rule, message, "warning", edit.program))
        if row.mismatches:
            shown = "\n".join(f.message for f in case.findings if f.rule != EDIT.id)
            case.failure = f"{row.mismatches} of {row.cases} cases do not match the reference\n{shown}"
        case.output = "\n".join(row.edits)
        out.cases.append(case)
    return out


def _placed(name: str, fresh_root: Path | None) -> str:
    if fresh_root is not None and name.startswith(FRESH):
        return str(fresh_root / name.removeprefix(FRESH))
    return name


def _edit(line: str, files: list[str]) -> Finding | None:
    """A changed or added line of a given program (verify.edits' words) as a finding at that line."""
    match = EDITED.match(line)
    if match is not None:
        message = f"line {match['what']} against the generated program: {match['text']}"
    else:
        match = REMOVED.match(line)
        if match is None:
            return None
        message = f"a line of the generated program removed after this line: {match['text']}"
    file = next((f for f in files if Path(f).name == match["file"]), match["file"])
    return Finding(EDIT.id, message, "warning", Location(file, max(1, int(match["line"]))))


def _cell_keys(cell_file: str | None) -> tuple[dict, dict] | None:
    if cell_file is None:
        return None
    try:
        text = Path(cell_file).read_text(encoding="utf-8")
        return tomllib.loads(text), key_lines(text)
    except (OSError, ValueError):
        return None  # the report still stands without the cell file's places


def _cell_place(keys, cell_file: str | None, text: str, problem: str) -> tuple[Location | None, str | None]:
    """The cell file's line of the pose a mismatching move is taught at: the key named as the move, under the entry
    (a [[table]] by its id or name) the case names, where there is exactly one."""
    move = MOVE.search(problem)
    if keys is None or move is None:
        return None, None
    data, lines = keys
    entry = entry_of(data, text.removesuffix(problem))
    path = key_under(lines, entry or (), move.group(1).strip(), data)
    if path is None:
        return None, None
    key = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in path).lstrip(".")
    return Location(cell_file, lines[path]), key
