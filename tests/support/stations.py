"""The station program in the tests: its files as text, an edited copy as a source, its cases run and swept."""

from __future__ import annotations

from dataclasses import replace

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
from codegen.kinds.station.cases import build_cases, inputs_for, run_options
from codegen.robot.expect import arm_of
from codegen.verify.programs import fresh_sources
from codegen.verify.report import Row
from codegen.verify.runner import run_cases

__all__ = ["build_cases", "files", "run", "source", "sweep", "verify"]


def _fresh(cell, target: str):
    return next(s for s in fresh_sources(cell, [target]) if s.kind == "station")


def files(cell, target: str) -> tuple[str, str | None]:
    """The station program's text (a UR socket program) and its data list (a KRL .dat), if any."""
    program = _fresh(cell, target)
    return program.files[0].text, program.files[1].text if len(program.files) > 1 else None


def source(cell, target: str, text: str | None = None, dat: str | None = None, label: str = "mutant"):
    """The station program as a source, its texts replaced where given."""
    program = _fresh(cell, target)
    # the program, its data list where given, then its other files as generated (a KRL channel's configuration)
    texts = [text or program.files[0].text, *([dat or program.files[1].text] if len(program.files) > 1 else [])]
    texts += [f.text for f in program.files[len(texts) :]]
    names = [f"{label}/{f.name.rsplit('/', 1)[-1]}" for f in program.files]
    new = tuple(SourceFile(n, t) for n, t in zip(names, texts, strict=True))
    return replace(program, files=new, origin=tuple(names), row=0)


def verify(cell, program, cases: list, step_limit: int = DEFAULT_STEP_LIMIT, first: bool = False) -> Row:
    """The row of the given station cases on the program (in this process; first: up to its first mismatch, as
    `codegen verify` stops a program's run there, for a test that asks only whether verify fails it)."""
    return run_cases(cell, program, cases, step_limit, first)


def sweep(cell, program, ids: range) -> Row:
    plan = cell.kinds[program.kind].verify
    row = Row(program.kind, program.target, program.ident, list(program.origin), verify=plan)
    plan.sweep(cell, program, program.load(), ids, DEFAULT_STEP_LIMIT, row)
    return row


def run(cell, target: str, program, case):
    """One case's trace on a loaded program."""
    t = get_target(target)
    return program.run(inputs_for(cell, t, case.reading), arm=arm_of(cell, target), **run_options(cell, t, case))
