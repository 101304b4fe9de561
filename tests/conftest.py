"""Shared fixtures: the demo cell, a helper that writes cell files, verify without the kinds' bulk runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.model.cell import DEMO_CELL, load_cell


@pytest.fixture(scope="session")
def demo_cell():
    return load_cell(DEMO_CELL)


@pytest.fixture
def write_cell(tmp_path: Path):
    def write(text: str, name: str = "cell.toml") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write


@pytest.fixture
def no_sweeps(monkeypatch):
    """verify's engine without the kinds' bulk runs (every station id that is not a station, run: a whole cell's
    long run, which the slow tests run on the same programs), for a command-line test that checks something else."""
    from dataclasses import replace

    from codegen.verify import engine

    real = engine.verify_cell

    def verify_cell(cell, files=(), targets=(), options=None):
        return real(cell, files, targets, replace(options or engine.Options(), sweeps=False))

    monkeypatch.setattr(engine, "verify_cell", verify_cell)
