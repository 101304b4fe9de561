"""A plant's cells as the report formats' results (reports.findings): each cell's findings, stored with its files
relative to the plant's folder (a cached result holds where the cell was when it ran), and a cell that could not
be done as an error."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

from codegen.plant.config import Plant
from codegen.plant.results import CellResult
from codegen.reports.findings import CellResult as Findings
from codegen.reports.findings import Finding, Location, TestCase
from codegen.reports.rules import CELL_ERROR


def stored(findings: Findings, plant: Plant) -> dict:
    """The findings as a plant's result keeps them: JSON, each file relative to the plant's folder."""
    return findings.moved(lambda file: Path(os.path.relpath(file, plant.root)).as_posix()).as_json()


def cell_findings(result: CellResult, command: str, plant: Plant, path: Path) -> Findings:
    """A cell's findings (its files where the plant is now, relative to the current folder where they are below it)
    and a test case in error for each row that could not be done (that has no findings of its own: check's files
    that do not parse have theirs)."""
    if result.findings is not None:  # the suite named by the cell's file: names may repeat in a plant, files not
        found = replace(
            Findings.from_json(result.findings).moved(lambda file: _shown(plant.root / file)), cell=result.cell
        )
    else:
        found = Findings(command, result.cell, _shown(path))
    for line in result.lines:
        if line.result == "error" and not any(case.target == line.target for case in found.cases):
            finding = Finding(CELL_ERROR.id, line.message, "error", Location(_shown(path)))
            found.cases.append(
                TestCase(
                    result.name or result.cell, line.target, "-", [_shown(path)], findings=[finding], error=line.message
                )
            )
    return found


def _shown(path: Path) -> str:
    """A path as a report names it: from the current folder where it lies below it, else whole."""
    whole = Path(os.path.normpath(path))
    try:
        return whole.relative_to(Path.cwd()).as_posix()
    except ValueError:
        return str(whole)
