"""Runs a program's cases (and bulk sweeps) against its kind's judgement and the common checks: an executor's tasks."""

from __future__ import annotations

import gc
import time

from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
from codegen.dialects.core.program import frozen_heap
from codegen.dialects.core.values import RunError, StepLimitError
from codegen.verify import clearance
from codegen.verify.checks import Checker, pose_errors
from codegen.verify.edits import message_renames
from codegen.verify.executor import Executor
from codegen.verify.report import Replay, Row, alike_key, case_text

_LOADED: dict = {}  # source -> program, in a worker (each program parsed once per process)
_RENAMES: dict = {}  # source -> the texts a given program changed (edits.message_renames), once per process
ONE_PROGRAM_FROM = 300  # stations: from here a worker holds one program at a time (a large cell's memory)


def large(cell) -> bool:
    """A cell of ONE_PROGRAM_FROM stations or more (in whichever section carries them)."""
    section = cell.stations_section()
    return section is not None and len(section.stations) >= ONE_PROGRAM_FROM


def _program(source, large: bool):
    if large and any(loaded != source for loaded in _LOADED):
        _LOADED.clear()  # a large cell's next program: the last one goes
        gc.collect()
    if source not in _LOADED:
        _LOADED[source] = source.load()
    return _LOADED[source]


def run_chunk(task) -> tuple[int, Row]:
    """One task: (cell, source, cases or a bulk range, step limit, stop at the first mismatch, keep the worst case's
    and the first mismatch's run[, per case whether its trace is swept against the cell's solids: default none]).
    Returns (the source's row, the partial row)."""
    cell, source, work, step_limit, first, keep, *rest = task
    swept = rest[0] if rest else ()
    model = source.model or cell
    kind = cell.kinds[source.kind].verify
    row = Row(source.kind, source.target, source.ident, list(source.origin))
    program = _program(source, large(model))
    start = time.perf_counter()
    with frozen_heap():
        if isinstance(work, range):
            kind.sweep(model, source, program, work, step_limit or DEFAULT_STEP_LIMIT, row)
        else:
            check = clearance.for_program(model, source.target, source.label, source.kind) if any(swept) else None
            _run_cases(model, kind, source, program, work, step_limit, row, first, keep, check, swept)
            row.seconds = time.perf_counter() - start  # the cases' time alone: cases/s is one program on one core
    return source.row, row


def run_cases(cell, source, cases: list, step_limit: int, first: bool = False) -> Row:
    """A program's row for the given cases of its kind (in this process)."""
    return run_chunk((cell, source, cases, step_limit, first, False))[1]


def _run_cases(
    model, kind, source, program, cases: list, step_limit: int, row: Row, first: bool = False, keep: bool = False,
    check: clearance.TraceClearance | None = None, swept: tuple[bool, ...] = (),
) -> None:
    checker = Checker(model, source.target)
    arm = checker.arm
    prefixes = kind.log_prefixes(model)
    if source not in _RENAMES:
        _RENAMES[source] = message_renames(model, source)
    renames = _RENAMES[source]
    for number, case in enumerate(cases):
        row.cases += 1
        row.categories[case.category] = row.categories.get(case.category, 0) + 1
        scenario = kind.scenario_of(case)
        row.scenarios[scenario] = row.scenarios.get(scenario, 0) + 1
        runaway = False
        pos, rot, figures, trace, setup, expected = [], [], None, None, None, None
        try:
            setup = kind.setup(model, source, case)
            trace = _run(program, setup, arm, step_limit)
            judgement = kind.judge(model, source, case, trace, setup)
        except StepLimitError as exc:
            problem, runaway = f"run error: {exc}; the remaining cases were not run", True
        except RunError as exc:
            problem = f"run error: {exc}"
        else:
            row.boundary += judgement.boundary
            problem = judgement.problem
            if problem is None and not judgement.accepted:
                problem = "the kind expects nothing of this case"
            if problem is None:
                problems = []
                for expected in judgement.accepted:
                    problem, pos, rot = checker.check(expected, trace, prefixes, renames)
                    if problem is None:
                        row.halts += trace.halted
                        figures = judgement.figures
                        pos, rot = [*pos, *judgement.errors[0]], [*rot, *judgement.errors[1]]
                        break
                    stops = (expected.halt is not None) != trace.halted
                    problems.append(((stops, -_followed(checker, expected, trace)), problem, pos, rot, expected))
                else:  # none accepted: the difference from the expectation the run followed (stops as it, then moves)
                    _, problem, pos, rot, expected = min(problems, key=lambda p: p[0])
            if problem is None and judgement.truth is not None:
                problem = judgement.truth
            # a move through a solid is named beside any other problem, unless the run stops at this case anyway
            if check is not None and swept[number] and not (first and problem is not None):
                breach = _clearance(check, setup, trace, row, case)
                if breach is not None:
                    problem = breach if problem is None else f"{problem}; {breach}"
            if expected is None and judgement.accepted:
                expected = judgement.accepted[0]
        row.pos_errors.extend(pos)
        row.rot_errors.extend(rot)
        if problem is None:
            row.moves += len(pos)
            named = lambda c=case: case_text(kind, model, c)  # noqa: E731 (asked at a new least)
            names = [getattr(m, "name", "") for m in expected.moves] if expected is not None else None
            row.arm.add(model, source.target, trace.moves, named, names)
            if figures:
                if row.figures is None:
                    row.figures = kind.figures()
                row.figures.count(case, figures)
        else:
            row.mismatch(f"{case_text(kind, model, case)}: {problem}", alike_key(problem))
        if keep:
            _keep(row, kind, model, case, setup, trace, expected, pos, rot, problem)
        if runaway or (first and problem is not None):
            break


def _followed(checker: Checker, expected, trace) -> int:
    """How many of the run's moves, from its first, are the expectation's (kind, and pose within tolerance): of the
    several a case accepts (a vision PC answering twice: either answer), the one a failing run took, whose
    difference is the run's fault (not the other answer's poses from its first corrected move)."""
    followed = 0
    for got, planned in zip(trace.moves, expected.moves, strict=False):
        if got.kind != planned.kind:
            break
        if planned.tcp2base is not None:
            pos, rot = pose_errors(got.tcp2base.tolist(), planned.tcp2base.tolist())
            pos_tol, rot_tol = planned.tolerance or (checker.pos_tol, checker.rot_tol)
            if not (pos <= pos_tol and rot <= rot_tol):
                break
        followed += 1
    return followed


def _clearance(check: clearance.TraceClearance, setup, trace, row: Row, case) -> str | None:
    """The trace swept against the cell's solids (and what the case stands and carries): the row's least clearance
    kept, the first move within the clearance the case's problem."""
    start = time.perf_counter()
    held = clearance.held_at_start(check, setup)
    least, breach = check.check(trace, setup.start_joints, held, case)
    row.clearance_seconds += time.perf_counter() - start
    row.clearance_traces += 1
    if least is not None and (row.clearance is None or least.distance < row.clearance.distance):
        row.clearance = least
    return None if breach is None else f"clearance: {breach.text(check.clearance)}"


def _run(program, setup, arm, step_limit: int):
    """One case's run; where the case ends in the controller's error naming setup.error, the trace until then
    (its `ended` the error), else the error raised."""
    try:
        return program.run(setup.inputs, **setup.run_options(arm, step_limit))
    except RunError as exc:
        trace = getattr(exc, "trace", None)
        if setup.error is None or trace is None or isinstance(exc, StepLimitError) or setup.error not in str(exc):
            raise
        return trace


def _keep(row: Row, kind, model, case, setup, trace, expected, pos, rot, problem) -> None:
    """The case as a Replay where it is the row's worst so far (the largest position error of a passing case) or its
    first mismatch."""
    worst = problem is None and bool(pos) and (row.worst is None or max(pos) > row.worst.pos_max)
    if not worst and (problem is None or row.failed is not None):
        return
    replay = Replay(
        case_text(kind, model, case),
        max(pos, default=0.0),
        max(rot, default=0.0),
        None if setup is None else setup.start_joints,
        trace,
        None if expected is None else [m.tcp2base for m in expected.moves],
        problem,
    )
    if worst:
        row.worst = replay
    else:
        row.failed = replay


def run_tasks(
    tasks: list, rows: list[Row], executor: Executor, progress=None, pinned: list[int] | None = None
) -> dict[int, float]:
    """Every task through the executor (pinned: a worker group per task, so a worker's tasks run in order and each
    loads its program once); each partial merged into its row in the tasks' order, wherever and whenever it ran.
    Returns when each row's last partial was merged (time.perf_counter)."""
    ended = {}
    for index, part in executor.map(run_chunk, tasks, pinned):
        rows[index].merge(part)
        ended[index] = time.perf_counter()
        if progress is not None:
            progress(part.cases + part.swept)
    return ended
