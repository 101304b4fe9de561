"""The belt programs as a vendor's engineer reads them: names, routines that move, waits, blends, payloads."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.dialects.core.values import RunError
from codegen.model.cell import load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
MOTION = re.compile(r"^\s*(PTP|LIN|CIRC|SPTP|SLIN|SCIRC|PTP_REL|LIN_REL)\b", re.MULTILINE)


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _src(cell) -> str:
    return next(f.text for f in first(cell, "kuka", "conveyor").files if f.name.endswith(".src"))


def test_no_kuka_variable_takes_a_data_types_name(cell):
    """AXIS is one of KSS's own structure types: the program's counter has a name of its own, and a program that
    declares a variable AXIS is refused when it loads."""
    program = first(cell, "kuka", "conveyor")
    program.load()
    mutant = edited(program, lambda text: re.sub(r"\bN_AX\b", "AXIS", text))
    with pytest.raises(RunError, match="AXIS is the name of a data type"):
        mutant.load()


def test_no_kuka_function_moves_the_arm(cell):
    """A function (DEFFCT) is called inside an expression: the routines that move the arm are DEF routines."""
    functions = re.findall(r"^DEFFCT\b.*?^ENDFCT", _src(cell), re.MULTILINE | re.DOTALL)
    assert functions
    moving = [f.splitlines()[0] for f in functions if MOTION.search(f)]
    assert not moving, moving
    assert re.search(r"^DEF CNV_PLACE_PART\(PLACED:OUT\)", _src(cell), re.MULTILINE)
