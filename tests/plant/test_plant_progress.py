"""Progress: bars (rich) where stderr is a terminal, nothing otherwise."""

from __future__ import annotations

import io

from codegen.plant import progress
from codegen.plant.config import Plant
from codegen.plant.results import CellResult, Line
from codegen.plant.run import run_plant


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_bars_only_on_a_terminal():
    assert progress.wanted(Terminal()) and not progress.wanted(io.StringIO())


def test_the_bars_count_cells_and_runs(tmp_path):
    seen = []

    def step(path, bars):
        seen.append(type(bars).__name__)
        bars.runs(5)
        return CellResult(path.name, path.stem, [Line(path.name, "ur", "point", 5, "ok", 0.0)])

    plant = Plant(tmp_path, (tmp_path / "a.toml", tmp_path / "b.toml"))
    with progress.progress_bars(2, True) as bars:
        bars.cell("a.toml")
        bars.runs(3)
        bars.done()
        task = bars.progress.tasks[bars.cells]
        assert task.completed == 1 and task.total == 2 and bars.progress.tasks[bars.current].completed == 3
    report = run_plant(plant, "verify", step, show_progress=True)
    assert seen == ["Bars", "Bars"] and report.exit_code == 0
    seen.clear()
    run_plant(plant, "verify", step, show_progress=False)
    assert seen == ["Quiet", "Quiet"]
