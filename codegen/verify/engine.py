"""verify_cell(s): every program of a cell (fresh, or the files given) run on its kind's cases and the common
scenarios, each trace judged by the kind and the common checks, one report per cell."""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

from codegen.dialects.core.values import RunError
from codegen.emit import EmitError
from codegen.robot.taught import ReachError
from codegen.verify import clearance
from codegen.verify.edits import edits
from codegen.verify.executor import Executor, LocalExecutor
from codegen.verify.programs import ProgramFilesError, ProgramSource, file_sources, fresh_sources
from codegen.verify.report import Report, Row
from codegen.verify.runner import large, run_tasks

CHUNK_CASES = 2000  # at most this many cases a task: a worker holds one chunk's expectations at a time
CELL_ERRORS = (ProgramFilesError, ReachError, EmitError, RunError)  # a cell verify cannot run: exit 2 (load: 1)


@dataclass(frozen=True)
class Options:
    """How much verify runs: random cases per station (or per program, as each kind reads it), the seed, the
    worker processes (0: one per core), the step limit of a run (a runaway loop stops there), a progress
    callback (cases done), and where the work runs (an executor.Executor; None: `jobs` processes here)."""

    cases: int = 1000
    seed: int = 0
    jobs: int = 0
    step_limit: int | None = None  # None: each kind's own (Setup.step_limit), else the interpreter's default
    progress: object = None
    first_mismatch: bool = False  # a program's cases stop at its first mismatch (a yes-or-no answer, fast)
    sweeps: bool = True  # the kinds' bulk runs too
    scenarios: frozenset[str] | None = None  # only the cases of these scenarios (None: every case)
    keep_replays: bool = False  # each row keeps its worst case's and first mismatch's run (report.Replay: the page)
    executor: Executor | None = None
    clearance: bool = True  # each checked trace swept against the cell's solids (codegen.verify.clearance)


@dataclass(frozen=True)
class CellRun:
    """One cell for verify_cells: the cell, paths of its programs on disk (none: every program rendered fresh) and
    the targets (none: the cell's)."""

    cell: object
    files: tuple = ()
    targets: tuple = ()


def verify_cell(cell, files=(), targets=(), options: Options | None = None) -> Report:
    """Verify of one cell (verify_cells of one, its error raised). files: paths of programs on disk (grouped into
    programs by each language's rule and matched to the cell's programs by name); none: every program of every
    kind, rendered fresh, for the targets asked (default: the cell's). ProgramFilesError: files that are not the
    cell's programs; RunError: a program that does not load here."""
    (report,) = verify_cells([CellRun(cell, tuple(files), tuple(targets))], options)
    if isinstance(report, Exception):
        raise report
    return report


def verify_cells(runs: list[CellRun], options: Options | None = None) -> list[Report | Exception]:
    """verify_cell of each run, the work of all of them spread over one executor: first each cell's programs (and
    the changes of the files given), one task per cell, then every program's case batches, the small cells' together
    and a large cell's alone. Per run its Report or, where the cell cannot be verified, its error (one of
    CELL_ERRORS, with the message verify_cell raises), the others verified all the same."""
    options = options or Options()
    executor = options.executor or LocalExecutor(options.jobs)
    limit, seed = options.step_limit, options.seed
    prepared = list(executor.map(prepare, [(run.cell, run.files, run.targets, limit, seed) for run in runs]))
    results: list[Report | Exception] = [_error(p) if isinstance(p, _Failed) else p for p in prepared]
    ready = [i for i, p in enumerate(results) if not isinstance(p, Exception)]
    big = [i for i in ready if large(runs[i].cell)]
    for batch in [[i for i in ready if i not in big], *([i] for i in big)]:
        if batch:
            reports = _verify_batch([runs[i].cell for i in batch], [results[i] for i in batch], options, executor)
            for i, report in zip(batch, reports, strict=True):
                results[i] = report
    return results


def prepare(task) -> tuple[list[ProgramSource], list[str], dict[int, list[str]]] | _Failed:
    """One cell's programs, its warnings and the changes of the files given against the generated programs (per
    source row), or the reason it cannot be verified: the first task of verify_cells, one per cell."""
    cell, files, targets, step_limit, seed = task
    try:
        names = list(targets) or list(cell.targets)
        warnings: list[str] = []
        for kind in cell.kinds.values():  # the reference's joints need every pose of every program within reach
            kind.writer.reach(cell, names)
        if not files:
            return _fresh(cell, names), warnings, {}
        sources, warnings = file_sources(cell, [Path(f) for f in files], tuple(targets))
        for source in sources:
            source.load()  # a file that does not load is reported before any case runs
        return sources, warnings, edits(cell, sources, step_limit, seed)
    except CELL_ERRORS as exc:
        return _Failed(next(cls for cls in CELL_ERRORS if isinstance(exc, cls)), str(exc))


def _verify_batch(cells: list, prepared: list, options: Options, executor: Executor) -> list[Report]:
    """The case batches of some cells in one map: each cell's rows numbered after the cells' before it (a large cell,
    whose tasks are pinned to workers, comes alone)."""
    rows, spans, tasks, pinned = [], [], [], None
    workers = executor.workers
    for cell, (own, _warnings, _edits) in zip(cells, prepared, strict=True):
        numbers = {row: len(rows) + i for i, row in enumerate(sorted({s.row for s in own}))}
        own = [replace(s, row=numbers[s.row]) for s in own]
        spans.append(range(len(rows), len(rows) + len(numbers)))
        rows += _rows(cell, own)
        own_tasks, own_pinned = _tasks(cell, own, options, workers)
        tasks += own_tasks
        pinned = own_pinned if len(cells) == 1 else None
    start = time.perf_counter()
    ended = run_tasks(tasks, rows, executor, options.progress, pinned)
    reports = []
    for cell, (own, warnings, changes), span in zip(cells, prepared, spans, strict=True):
        numbers = sorted({s.row for s in own})
        for row, lines in changes.items():
            rows[span[numbers.index(row)]].edits = lines
        wall = max((ended.get(i, start) for i in span), default=start) - start
        own_rows = rows[span.start : span.stop]
        reports.append(Report(cell.name, own_rows, options.seed, options.cases, wall, workers, warnings))
    return reports


def verify_sources(cell, sources: list[ProgramSource], options: Options) -> tuple[list[Row], int]:
    """The rows of the given programs (verify_cell's work once it has them; tests give their own programs)."""
    executor = options.executor or LocalExecutor(options.jobs)
    (report,) = _verify_batch([cell], [(sources, [], {})], options, executor)
    return report.rows, report.workers


@dataclass(frozen=True)
class _Failed:
    """A cell's error as a prepare task returns it: its class (one of CELL_ERRORS, as a subclass's own arguments
    need not come through pickling) and message."""

    error: type
    message: str


def _error(failed: _Failed) -> Exception:
    return failed.error(failed.message)


def _fresh(cell, names: list[str]) -> list[ProgramSource]:
    """Each kind's programs rendered from the models it verifies them against (a kind may add variants of the
    cell, e.g. extra edge-case stations, counted in the same row)."""
    out: list[ProgramSource] = []
    rows: dict[tuple, int] = {}

    def row_of(plan, target: str) -> int:
        key = (plan.kind, target, plan.index)
        return rows.setdefault(key, len(rows))

    for kind in cell.kinds.values():
        for model, sweep in kind.verify.models(cell):
            out += fresh_sources(model, names, None if model is cell else model, row_of, {kind.name}, sweep)
    return sorted(out, key=lambda s: s.row)


def _rows(cell, sources: list[ProgramSource]) -> list[Row]:
    rows: dict[int, Row] = {}
    for source in sources:
        if source.row not in rows:
            plan = cell.kinds[source.kind].verify
            rows[source.row] = Row(source.kind, source.target, source.ident, list(source.origin), verify=plan)
        elif source.model is None:  # the cell's own program names the row's files
            rows[source.row].files = list(source.origin)
    return [rows[i] for i in sorted(rows)]


def _tasks(cell, sources: list[ProgramSource], options: Options, workers: int):
    """(cell, source, cases or a bulk range, step limit, first mismatch, keep replays) tasks; for a large cell each
    source's tasks pinned to one worker (the workers sharing a program would each load it)."""
    tasks, owner = [], []
    for source in sources:
        kind = cell.kinds[source.kind].verify
        model = source.model or cell
        cases = kind.cases(model, source, options.cases, options.seed)
        if options.scenarios is not None:
            cases = [case for case in cases if kind.scenario_of(case) in options.scenarios]
        chunk = max(1, min(CHUNK_CASES, -(-len(cases) // max(4, 2 * workers))))
        if options.first_mismatch:  # one answer per program: its cases in one run, stopped at the first mismatch
            chunk = max(1, len(cases))
        limit, first, keep = options.step_limit, options.first_mismatch, options.keep_replays
        swept = [False] * len(cases)
        if options.clearance:
            swept = clearance.selected([c.category for c in cases], [kind.scenario_of(c) for c in cases])
        own = [(cell, source, cases[i : i + chunk], limit, first, keep, tuple(swept[i : i + chunk]))
               for i in range(0, len(cases), chunk)]
        if options.sweeps:
            own += [(cell, source, ids, limit, first, keep) for ids in kind.sweeps(model, source, workers)]
        tasks += own
        owner += [source.row] * len(own)
    if not (large(cell) and len(sources) > 1) or workers <= 1 or len(sources) < workers:
        return tasks, None
    programs = sorted(set(owner))
    worker_of = {row: i % workers for i, row in enumerate(programs)}
    return tasks, [worker_of[row] for row in owner]
