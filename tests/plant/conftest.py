"""A tiny plant in tmp_path: copies of small example cells, and a stand-in for verify_cells counting its cells."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from codegen.model.cell import EXAMPLE_PLANT
from codegen.verify.report import Report, Row

# two cells of the example plant whose programs render quickly
CELLS = {"a/tray.toml": "pallets/tray_dtrans.toml", "b/gate.toml": "stations/warehouse_dtrans.toml"}


@pytest.fixture
def plant(tmp_path: Path) -> Path:
    root = tmp_path / "plant"
    for name, source in CELLS.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(EXAMPLE_PLANT / source, root / name)
    return root


class FakeVerify:
    """verify_cells' stand-in: per run one row per target, passing unless the cell's name is in `failing`; each
    cell verified recorded by its name."""

    def __init__(self):
        self.calls: list[str] = []
        self.failing: set[str] = set()
        self.mismatch = "random 1: position off by 3 mm"  # a failing cell's mismatch, as verify words one

    def __call__(self, runs, options=None) -> list[Report]:
        return [self.one(run.cell, run.targets, options) for run in runs]

    def one(self, cell, targets, options) -> Report:
        self.calls.append(cell.name)
        rows = []
        for target in targets or cell.targets:
            row = Row(next(iter(cell.sections)), target, cell.name, [f"<fresh>/{cell.name}"], cases=options.cases)
            if cell.name in self.failing:
                row.mismatch(self.mismatch)
            rows.append(row)
        return Report(cell.name, rows, options.seed, options.cases)


@pytest.fixture
def fake_verify(monkeypatch) -> FakeVerify:
    fake = FakeVerify()
    monkeypatch.setattr("codegen.plant.verify.verify_cells", fake)
    return fake
