"""The belt's fourth review: the UR program tracks by the robot's own decoder's scale (`calibrate conveyor --ticks`),
the line's cycle stop ends a wait above a standing belt, and the headers say what the integrator must set."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
PLANT_UR = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "plant" / "belts" / "belt_ur.toml"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _mutant(cell, target: str, pairs: list[tuple[str, str]], label: str):
    program = first(cell, target, "conveyor")
    for old, _new in pairs:
        assert sum(f.text.count(old) for f in program.files) == 1, old

    def edit(text: str) -> str:
        for old, new in pairs:
            text = text.replace(old, new)
        return text

    return program, edited(program, edit, label)


def _run(cell, program, category: str):
    chosen = [c for c in cases(cell) if c.category == category]
    assert len(chosen) == 1
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def _ur_text(cell) -> str:
    return "".join(f.text for f in first(cell, "ur", "conveyor").files)


def test_the_bundled_ur_program_tracks_by_the_robots_own_scale_and_says_so(cell):
    text = _ur_text(cell)
    assert "CNV_TICKS_PER_MM = 5.092647" in text and "CNV_TICKS_PER_M = 5092.647" in text
    assert "/ CNV_TICKS_PER_MM" in text  # the latched ticks placed by the robot's scale
    assert "The scale is the robot's own decoder's: the cell's [conveyor] ticks_per_mm" in text
    plant = _ur_text(load_cell(PLANT_UR))  # a cell without ticks_per_mm: the PLC's scale, said so
    assert "The scale is the PLC counter's" in plant and "CNV_TICKS_PER_MM = -8.122679" in plant


@pytest.mark.parametrize(
    ("label", "pairs"),
    [
        # the latched ticks placed by the PLC's counts per mm, as the program did before its own scale
        ("latch by the PLC's scale", [("latched) / CNV_TICKS_PER_MM", "latched) / CNV_COUNTS_PER_MM")]),
        # tracking at the PLC's scale and sign
        (
            "tracking by the PLC's scale",
            [
                ("CNV_TICKS_PER_M = 5092.647000", "CNV_TICKS_PER_M = 8122.679000"),
                (
                    "CNV_DIR = p[-0.499994000, 0.866029000, 0.000035000",
                    "CNV_DIR = p[0.499994000, -0.866029000, -0.000035000",
                ),
            ],
        ),
    ],
)
def test_a_ur_program_on_the_plcs_scale_fails_verify(cell, label, pairs):
    """The robot's own encoder counts at 5.09 ticks/mm, up, the PLC's at -8.12 counts/mm: the program passes, and the
    program that reads its own ticks by the PLC's scale fails."""
    program, mutant = _mutant(cell, "ur", pairs, label)
    assert _run(cell, program, "constant_speed").mismatches == 0
    assert _run(cell, mutant, "constant_speed").mismatches == 1
