"""verify_cell: every program of a cell (fresh, or the files given) run on its kind's cases and the common
scenarios, each trace judged by the kind and the common checks, one report."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, replace
from pathlib import Path

from codegen.protocol import get_kind, kinds
from codegen.verify.edits import edits
from codegen.verify.programs import ProgramSource, file_sources, fresh_sources
from codegen.verify.report import Report, Row
from codegen.verify.runner import ONE_PROGRAM_FROM, run_tasks

CHUNK_CASES = 2000  # at most this many cases a task: a worker holds one chunk's expectations at a time


@dataclass(frozen=True)
class Options:
    """How much verify runs: random cases per station (or per program, as each kind reads it), the seed, the
    worker processes (0: one per core), the step limit of a run (a runaway loop stops there), a progress
    callback (cases done)."""

    cases: int = 1000
    seed: int = 0
    jobs: int = 0
    step_limit: int | None = None  # None: each kind's own (Setup.step_limit), else the interpreter's default
    progress: object = None
    first_mismatch: bool = False  # a program's cases stop at its first mismatch (a yes-or-no answer, fast)
    sweeps: bool = True  # the kinds' bulk runs too
    scenarios: frozenset[str] | None = None  # only the cases of these scenarios (None: every case)
    keep_replays: bool = False  # each row keeps its worst case's and first mismatch's run (report.Replay: the page)


def verify_cell(cell, files=(), targets=(), options: Options | None = None) -> Report:
    """The only entry of verify. files: paths of programs on disk (grouped into programs by each language's
    rule and matched to the cell's programs by name); none: every program of every kind, rendered fresh, for
    the targets asked (default: the cell's). ProgramFilesError: files that are not the cell's programs;
    RunError: a program that does not load here."""
    options = options or Options()
    names = list(targets) or list(cell.targets)
    warnings: list[str] = []
    for kind in kinds().values():  # the reference's joints need every pose of every program within reach
        kind.reach(cell, names)
    if files:
        sources, warnings = file_sources(cell, [Path(f) for f in files], tuple(targets))
        for source in sources:
            source.load()  # a file that does not load is reported before any case runs
    else:
        sources = _fresh(cell, names)
    start = time.perf_counter()
    rows, workers = verify_sources(cell, sources, options)
    if files:  # what a hand edit changes, beside the program the cell generates
        numbers = sorted({s.row for s in sources})
        for row, lines in edits(cell, sources, options.step_limit, options.seed).items():
            rows[numbers.index(row)].edits = lines
    return Report(cell.name, rows, options.seed, options.cases, time.perf_counter() - start, workers, warnings)


def verify_sources(cell, sources: list[ProgramSource], options: Options) -> tuple[list[Row], int]:
    """The rows of the given programs (verify_cell's work once it has them; tests give their own programs)."""
    numbers = {row: i for i, row in enumerate(sorted({s.row for s in sources}))}  # rows 0.. in their order
    sources = [replace(s, row=numbers[s.row]) for s in sources]
    rows = _rows(sources)
    workers = options.jobs or os.cpu_count() or 1
    tasks, pinned = _tasks(cell, sources, options, workers)
    run_tasks(tasks, rows, workers, options.progress, pinned)
    return rows, workers


def _fresh(cell, names: list[str]) -> list[ProgramSource]:
    """Each kind's programs rendered from the models it verifies them against (a kind may add variants of the
    cell, e.g. extra edge-case stations, counted in the same row)."""
    out: list[ProgramSource] = []
    rows: dict[tuple, int] = {}

    def row_of(plan, target: str) -> int:
        key = (plan.kind, target, plan.index)
        return rows.setdefault(key, len(rows))

    for kind in kinds().values():
        for model, sweep in kind.verify_models(cell):
            out += fresh_sources(model, names, None if model is cell else model, row_of, {kind.name}, sweep)
    return sorted(out, key=lambda s: s.row)


def _rows(sources: list[ProgramSource]) -> list[Row]:
    rows: dict[int, Row] = {}
    for source in sources:
        if source.row not in rows:
            rows[source.row] = Row(source.kind, source.target, source.ident, list(source.origin))
        elif source.model is None:  # the cell's own program names the row's files
            rows[source.row].files = list(source.origin)
    return [rows[i] for i in sorted(rows)]


def _tasks(cell, sources: list[ProgramSource], options: Options, workers: int):
    """(cell, source, cases or a bulk range, step limit, first mismatch, keep replays) tasks; for a large cell each
    source's tasks pinned to one worker (the workers sharing a program would each load it)."""
    tasks, owner = [], []
    for source in sources:
        kind = get_kind(source.kind)
        model = source.model or cell
        cases = kind.verify_cases(model, source, options.cases, options.seed)
        if options.scenarios is not None:
            cases = [case for case in cases if kind.scenario_of(case) in options.scenarios]
        chunk = max(1, min(CHUNK_CASES, -(-len(cases) // max(4, 2 * workers))))
        if options.first_mismatch:  # one answer per program: its cases in one run, stopped at the first mismatch
            chunk = max(1, len(cases))
        limit, first, keep = options.step_limit, options.first_mismatch, options.keep_replays
        own = [(cell, source, cases[i : i + chunk], limit, first, keep) for i in range(0, len(cases), chunk)]
        if options.sweeps:
            own += [(cell, source, ids, limit, first, keep) for ids in kind.sweeps(model, source, workers)]
        tasks += own
        owner += [source.row] * len(own)
    large = len(cell.stations) >= ONE_PROGRAM_FROM and len(sources) > 1
    if not large or workers <= 1 or len(sources) < workers:
        return tasks, None
    programs = sorted(set(owner))
    worker_of = {row: i % workers for i, row in enumerate(programs)}
    return tasks, [worker_of[row] for row in owner]
