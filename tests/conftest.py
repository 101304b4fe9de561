"""Shared fixtures: the demo cell and a helper that writes cell files."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.controllers import target_names
from codegen.model.cell import DEMO_CELL, load_cell

MINIMAL_CELL = """\
[cell]
name = "bench"
targets = {TARGETS}
pose_format = "xyzabc"
[cell.camera]
angle_sign = -1
[cell.limits]
max_shift_mm = 10.0
max_rotation_deg = 10.0
[[station]]
id = 1
name = "lathe_1"
mark = [600.0, -250.0, 2.0]
[station.poses]
approach = [650.0, -100.0, 400.0, 90.0, 0.0, 180.0]
chuck = [700.0, -100.0, 300.0, 90.0, 0.0, 180.0]
[[station]]
id = 2
name = "mill_1"
mark = [640.0, 210.0, 0.0]
[station.poses]
vise = [700.0, 50.0, 260.0, -90.0, 15.0, 180.0]
""".replace("{TARGETS}", repr(list(target_names())).replace("'", '"'))


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
