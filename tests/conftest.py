"""Shared fixtures: the demo cell and a helper that writes cell files."""

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
