"""Every cell of a plant through one command's step, in the plant's order, into one report."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from codegen.plant.config import Plant
from codegen.plant.progress import Quiet, progress_bars
from codegen.plant.results import CellResult, PlantReport

Step = Callable[[Path, Quiet], CellResult]  # a cell file and the progress -> its result (never raises for bad input)


def run_plant(plant: Plant, command: str, step: Step, show_progress: bool = False) -> PlantReport:
    """Each cell's result by `step`; a cell that fails is its own row and the next one runs."""
    start = time.perf_counter()
    results = []
    with progress_bars(len(plant.cells), show_progress) as bars:
        for path in plant.cells:
            bars.cell(plant.label(path))
            results.append(step(path, bars))
            bars.done()
    return plant_report(plant, command, results, time.perf_counter() - start)


def plant_report(plant: Plant, command: str, results: list[CellResult], seconds: float) -> PlantReport:
    """The plant's report of its cells' results, with a note for each .toml that is no cell."""
    notes = [f"not a cell file (no [cell] table), skipped: {name}" for name in plant.skipped]
    label = plant.name or str(plant.config or plant.root)
    return PlantReport(command, label, results, seconds, notes)
