"""`codegen verify` of a generated program against its cell, in a child process (cancellable), as diagnostics."""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import re
import signal
import sys
from dataclasses import dataclass, field
from pathlib import Path

from lsprotocol import types

from codegen.lsp.diagnostics import SOURCE, word_range

FILE_LINE = re.compile(r"([\w.$-]+\.\w+):(\d+)")
LINE = re.compile(r"\bline (\d+)\b")
DEFAULT_CASES = 20  # random cases per station: the scenarios' own cases run besides; a minute's work at most


@dataclass
class Outcome:
    """What a verify run said: diagnostics per file path, a one-line summary, and whether it passed."""

    diagnostics: dict[str, list[types.Diagnostic]] = field(default_factory=dict)
    summary: str = ""
    ok: bool = False


def command(cell: Path, files: list[str], cases: int) -> list[str]:
    """The verify command line: this interpreter's codegen, JSON out."""
    return [sys.executable, "-m", "codegen", "verify", str(cell), *files, "--json", "--cases", str(cases)]


async def run_verify(cell: Path, files: list[str], texts: dict[str, str], cases: int = DEFAULT_CASES) -> Outcome:
    """Verify the program's files (on disk) against the cell. Cancelling the awaiting task ends the child process."""
    process = await asyncio.create_subprocess_exec(
        *command(cell, files[:1], cases),
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
        stdin=asyncio.subprocess.DEVNULL,
        start_new_session=True,  # its own process group: cancelling ends verify's worker processes too
    )
    try:
        out, err = await process.communicate()
    except asyncio.CancelledError:
        if process.returncode is None:
            with contextlib.suppress(ProcessLookupError):
                if hasattr(os, "killpg"):
                    os.killpg(process.pid, signal.SIGKILL)
                else:  # no process groups (Windows): the verify process itself
                    process.kill()
            await process.wait()
        raise
    return outcome(process.returncode or 0, out.decode(errors="replace"), err.decode(errors="replace"), files, texts)


def outcome(code: int, out: str, err: str, files: list[str], texts: dict[str, str]) -> Outcome:
    """Verify's JSON report as diagnostics: each first mismatch and each EDIT line at the line it names (the
    program file's first line where it names none); verify refusing (exit 2) as one error there."""
    result = Outcome({name: [] for name in files})
    try:
        report = json.loads(out) if out.strip() else None
    except json.JSONDecodeError:
        report = None
    if report is None:
        message = err.strip().splitlines()[-1] if err.strip() else f"verify ended with exit {code}"
        result.diagnostics[files[0]].append(_at(files, texts, message, "verify", types.DiagnosticSeverity.Error))
        result.summary = f"verify could not run: {message}"
        return result
    mismatches = 0
    for program in report.get("programs", []):
        mismatches += program.get("mismatches", 0)
        for text in program.get("first_mismatches", []):
            file, diagnostic = _placed(files, texts, text, "verify-mismatch", types.DiagnosticSeverity.Error)
            result.diagnostics[file].append(diagnostic)
        for text in program.get("edits", []):
            file, diagnostic = _placed(files, texts, text, "verify-edit", types.DiagnosticSeverity.Information)
            result.diagnostics[file].append(diagnostic)
    result.ok = bool(report.get("ok"))
    cases = sum(p.get("cases", 0) for p in report.get("programs", []))
    result.summary = f"verify against {report.get('cell')}: {cases} cases, " + (
        "no mismatch" if result.ok else f"{mismatches} mismatches"
    )
    return result


def _placed(files, texts, text: str, code: str, severity) -> tuple[str, types.Diagnostic]:
    names = {Path(f).name: f for f in files}
    for match in FILE_LINE.finditer(text):
        if match[1] in names:
            file = names[match[1]]
            return file, _diagnostic(texts.get(file, ""), int(match[2]), text, code, severity)
    found = LINE.search(text)
    line = int(found[1]) if found else 1
    return files[0], _diagnostic(texts.get(files[0], ""), line, text, code, severity)


def _at(files, texts, text, code, severity) -> types.Diagnostic:
    return _diagnostic(texts.get(files[0], ""), 1, text, code, severity)


def _diagnostic(text: str, line: int, message: str, code: str, severity) -> types.Diagnostic:
    return types.Diagnostic(
        range=word_range(text, line, 0), message=message, severity=severity, code=code, source=SOURCE
    )
