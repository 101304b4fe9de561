"""`codegen check`'s findings as the neutral model: a test case per program (its files), a finding per check finding."""

from __future__ import annotations

from codegen.reports.findings import CellResult, Finding, Location, TestCase

LEVEL = {"error": "error", "unsupported": "error", "warning": "warning"}  # check's severities as result levels


def check_result(programs: list[tuple[str, list[str]]], findings: list) -> CellResult:
    """programs: (target, the program's file names, program file first); findings: check's (file, line, column,
    severity, code, message), each counted in the program holding its file (a file of none: a case of its own)."""
    out = CellResult("check", "", None)
    owner = {}
    for target, files in programs:
        case = TestCase("", target, files[0], list(files))
        out.cases.append(case)
        owner.update({name: case for name in files})
    for f in findings:
        case = owner.get(f.file)
        if case is None:
            case = owner[f.file] = TestCase("", "", f.file, [f.file])
            out.cases.append(case)
        where = Location(f.file, max(f.line, 0), max(f.column, 0))
        case.findings.append(Finding(f"check/{f.code}", f.message, LEVEL.get(f.severity, "warning"), where))
    for case in out.cases:
        if case.findings:
            case.failure = "\n".join(_text(f) for f in case.findings)
    return out


def _text(f: Finding) -> str:
    where = f.program.file if not f.program.line else f"{f.program.file}:{f.program.line}:{f.program.column}"
    return f"{where}: {f.level}: {f.message} [{f.rule}]"
