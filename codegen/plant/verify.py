"""One cell of a plant verified (verify_cell) into its table row, or its stored result when nothing it depends on
has changed."""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass
from pathlib import Path

from codegen.dialects.core.values import RunError
from codegen.emit import EmitError
from codegen.model.cell import CellError, cell_from_dict, read_cell_data
from codegen.plant.cache import Cache, verify_key
from codegen.plant.config import Plant
from codegen.plant.progress import Quiet
from codegen.plant.results import CellResult, Line, cell_kinds, error_result
from codegen.robot.taught import ReachError
from codegen.verify.engine import Options, verify_cell
from codegen.verify.programs import ProgramFilesError

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


def verify_plant_cell(plant: Plant, path: Path, how: PlantVerify, progress: Quiet | None = None) -> CellResult:
    """A cell's verify result: from the cache when an entry of its key is there (a failing result too: verify is
    deterministic, and a cached mismatch still fails the run), else verified and stored. A cell that cannot be
    verified (bad file, out of reach, ...) is an error row."""
    progress = progress or Quiet()
    label = plant.label(path)
    start = time.perf_counter()
    try:
        data, raw = read_cell_data(path)
    except CellError as exc:
        return error_result(label, str(exc), time.perf_counter() - start)
    key = verify_key(raw, [], how.key_options())
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
    result = _verified(data, raw, path, label, how, progress, start)
    result.notes = notes + result.notes
    if how.cache is not None and all(line.result != "error" for line in result.lines):
        problem = how.cache.put(key, result.as_json())
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


def _verified(data: dict, raw: bytes, path: Path, label: str, how: PlantVerify, progress, start: float) -> CellResult:
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
    options = Options(how.cases, how.seed, how.jobs, how.step_limit, progress.runs)
    try:
        report = verify_cell(cell, [], targets, options)
    except (ProgramFilesError, ReachError, EmitError, RunError) as exc:
        return error_result(label, f"{path}: {exc}", time.perf_counter() - start, cell.name)
    if not report.rows:
        return error_result(label, f"{path}: no program to verify for the targets asked", 0.0, cell.name)
    problems = [
        f"MISMATCH {row.target} {row.program}: {row.mismatches} cases; first: {row.first_mismatches[0]}"
        for row in report.rows
        if row.mismatches
    ]
    line = Line(
        label,
        ",".join(targets),
        cell_kinds(cell),
        sum(row.cases for row in report.rows),
        "ok" if report.ok else "mismatch",
        time.perf_counter() - start,
        "\n".join(problems),
    )
    return CellResult(label, cell.name, [line], report.as_json(), notes=[*cell.warnings, *report.warnings])
