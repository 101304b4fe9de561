"""The runs a cell's page shows: each program run by the interpreter on nominal cases of its kind, as verify does."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from codegen.dialects.core.machine import Trace
from codegen.dialects.core.values import RunError
from codegen.robot.expect import arm_of
from codegen.verify.plan import SCENARIOS
from codegen.verify.programs import ProgramSource, fresh_sources
from codegen.verify.report import case_text

STEP_LIMIT = 2_000_000  # the longest nominal run (a full stack of boxes) runs well under this; a runaway stops here


@dataclass
class Run:
    """One run of a program: what it is (the case's category and the kind's words for it), where the arm stood
    when it started (deg, None: no arm), the interpreter's trace and the poses the reference planned (4x4 mm,
    or None where the page shows no reference)."""

    what: str
    start_joints: np.ndarray | None
    trace: Trace
    reference: list | None = None


@dataclass
class ProgramRuns:
    """A program of one target and the runs shown for it: its name, kind, files (the program file first, with its
    text for the page's source lines) and the runs in order."""

    target: str
    program: str
    kind: str
    files: list[tuple[str, str]]
    runs: list[Run] = field(default_factory=list)
    problem: str | None = None  # why no run is shown (a program that does not load or run here)


def _station_of(case) -> int | None:
    """The station a station program's case is for (its reading names it; None for other kinds' cases)."""
    return getattr(getattr(case, "reading", None), "station_id", None)


def nominal_cases(cell, source: ProgramSource, kind) -> list:
    """The candidates for a nominal run, in the kind's order: its own cases (not one of the common scenarios, which
    each disturb a run on purpose) that start at home."""
    cases = kind.cases(cell, source, 1, 0)
    return [c for c in cases if kind.scenario_of(c) not in SCENARIOS and getattr(c, "start", "home") == "home"]


def run_case(cell, source: ProgramSource, program, case) -> Run:
    """One case run as verify runs it (the kind's setup, the target's arm)."""
    kind = cell.kinds[source.kind].verify
    setup = kind.setup(cell, source, case)
    trace = program.run(setup.inputs, **setup.run_options(arm_of(cell, source.target), STEP_LIMIT))
    start = None if setup.start_joints is None else np.asarray(setup.start_joints, dtype=float)
    return Run(describe(cell, kind, case), start, trace)


def describe(cell, kind, case) -> str:
    return case_text(kind, cell, case)


def nominal_runs(cell, target: str) -> list[ProgramRuns]:
    """Each program of the target with its nominal run: the first candidate case that runs to its end without a stop
    (one per station for the station program: one pass of each station; for the other kinds one run: a full stack,
    a part from the belt, a TCP calibration)."""
    out = []
    for source in fresh_sources(cell, [target]):
        kind = cell.kinds[source.kind].verify
        entry = ProgramRuns(target, source.ident, source.kind, [(Path(f.name).name, f.text) for f in source.files])
        out.append(entry)
        try:
            program = source.load()
            shown: set = set()
            for case in nominal_cases(cell, source, kind):
                station = _station_of(case)
                if station in shown:
                    continue
                run = run_case(cell, source, program, case)
                if run.trace.halted or not run.trace.moves:
                    continue
                entry.runs.append(run)
                shown.add(station)
                if station is None:
                    break
        except RunError as exc:
            entry.problem = f"the program did not run here: {exc}"
        if not entry.runs and entry.problem is None:
            entry.problem = "none of its cases runs to its end without a stop"
    return out
