"""A plant's cells verified together (verify_cells) into their rows, or their stored results where nothing changed."""

from __future__ import annotations

import hashlib
import os
import time
from dataclasses import dataclass
from pathlib import Path

from codegen.model.cell import CellError, cell_from_dict, read_cell_data
from codegen.plant.cache import Cache, verify_key
from codegen.plant.config import Plant
from codegen.plant.findings import stored
from codegen.plant.progress import Quiet
from codegen.plant.results import CellResult, Line, cell_kinds, error_result
from codegen.reports.from_verify import verify_result
from codegen.verify.engine import CellRun, Options, verify_cells

CACHED = {"ok": "cached", "mismatch": "cached mismatch"}


@dataclass(frozen=True)
class PlantVerify:
    """What each cell is verified with: the plant's targets (empty: each cell's own), the cases, seed and step
    limit, the worker processes, and the cache (None: --no-cache)."""

    targets: tuple[str, ...] = ()
    cases: int = 1000
    seed: int = 0
    step_limit: int | None = None
    jobs: int = 0
    cache: Cache | None = None

    def key_options(self) -> dict:
        """The options that change a result (the workers do not)."""
        return {"targets": sorted(self.targets), "cases": self.cases, "seed": self.seed, "step_limit": self.step_limit}


@dataclass
class Pending:
    """A cell whose result is not stored: its model and targets for verify_cells, and what its row needs after."""

    label: str
    path: Path
    cell: object
    targets: list[str]
    key: str
    notes: list[str]
    start: float


def verify_plant(plant: Plant, how: PlantVerify, executor=None, progress: Quiet | None = None) -> list[CellResult]:
    """Every cell's verify result in the plant's order: stored ones from the cache (a failing result too: verify is
    deterministic, and a cached mismatch still fails the run), the others verified together through one executor
    (verify_cells: the cells' programs and their case batches spread over its workers) and stored. A cell that
    cannot be verified (bad file, out of reach, ...) is an error row; the others run all the same."""
    progress = progress or Quiet()
    looked = [lookup(plant, path, how) for path in plant.cells]
    pending = [item for item in looked if isinstance(item, Pending)]
    if pending:
        progress.cell(f"{len(pending)} of {len(looked)} cells")
        runs = [CellRun(item.cell, (), tuple(item.targets)) for item in pending]
        options = Options(how.cases, how.seed, how.jobs, how.step_limit, progress.runs, executor=executor)
        reports = verify_cells(runs, options)
        done = iter(finish(item, report, how, plant) for item, report in zip(pending, reports, strict=True))
        looked = [next(done) if isinstance(item, Pending) else item for item in looked]
    return looked


def lookup(plant: Plant, path: Path, how: PlantVerify) -> CellResult | Pending:
    """A cell's stored result, its error or skipped row, or what verifying it needs."""
    label = plant.label(path)
    start = time.perf_counter()
    try:
        data, raw = read_cell_data(path)
    except CellError as exc:
        return error_result(label, str(exc), time.perf_counter() - start)
    # the output folder too: a finding places the fresh programs there (as the plant's folder sees it)
    out = Path(os.path.relpath(plant.output(), plant.root)).as_posix()
    key = verify_key(raw, [], {**how.key_options(), "out": out})
    notes = []
    if how.cache is not None:
        stored = how.cache.get(key)
        if stored is not None:
            try:
                return _from_cache(stored, label, time.perf_counter() - start)
            except (KeyError, TypeError, ValueError):
                how.cache.unreadable.add(key)
        if key in how.cache.unreadable:
            notes.append(f"cache entry {how.cache.path(key)} was unreadable: verified again and rewritten")
    try:
        cell = cell_from_dict(data, source=str(path), sha256=hashlib.sha256(raw).hexdigest())
    except (CellError, RecursionError) as exc:
        message = str(exc) if isinstance(exc, CellError) else f"{path}: tables or arrays nested too deeply"
        return error_result(label, message, time.perf_counter() - start)
    targets = [t for t in cell.targets if not how.targets or t in how.targets]
    if not targets:
        line = Line(
            label, "-", "", None, "skipped", 0.0, f"none of its targets ({', '.join(cell.targets)}) is the plant's"
        )
        return CellResult(label, cell.name, [line], notes=list(cell.warnings))
    return Pending(label, path, cell, targets, key, notes, start)


def finish(item: Pending, report, how: PlantVerify, plant: Plant) -> CellResult:
    """The row of a verified cell (its Report, or the error verify_cells gave for it alone) with its findings (its
    fresh programs placed where generate writes them), stored in the cache unless it is an error."""
    result = _row(item, report)
    if not isinstance(report, Exception) and report.rows:
        result.findings = stored(verify_result(report, str(item.path), plant.output()), plant)
    result.notes = item.notes + result.notes
    if how.cache is not None and all(line.result != "error" for line in result.lines):
        problem = how.cache.put(item.key, result.as_json())
        if problem is not None:
            result.notes.append(problem)
    return result


def _from_cache(stored: dict, label: str, seconds: float) -> CellResult:
    result = CellResult.from_json(stored)
    for line in result.lines:
        line.result = CACHED[line.result]
        line.cell = label
        line.seconds = seconds
    result.cell, result.cached = label, True
    return result


def _row(item: Pending, report) -> CellResult:
    label, cell, path = item.label, item.cell, item.path
    if isinstance(report, Exception):
        return error_result(label, f"{path}: {report}", time.perf_counter() - item.start, cell.name)
    if not report.rows:
        return error_result(label, f"{path}: no program to verify for the targets asked", 0.0, cell.name)
    problems = [
        f"MISMATCH {row.target} {row.program}: {row.mismatches} cases; first: {row.first_mismatches[0]}"
        for row in report.rows
        if row.mismatches
    ]
    line = Line(
        label,
        ",".join(item.targets),
        cell_kinds(cell),
        sum(row.cases for row in report.rows),
        "ok" if report.ok else "mismatch",
        report.wall_seconds,  # its own batches' time: the time here runs to the end of all the cells verified together
        "\n".join(problems),
    )
    result = CellResult(label, cell.name, [line], report.as_json(), notes=[*cell.warnings, *report.warnings])
    result.warnings = report.margin_warnings()
    return result
