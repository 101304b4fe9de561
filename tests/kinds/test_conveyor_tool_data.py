"""The belt program's tool where a program load does not reset it: ABB's system module, KUKA's numbered tool."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.emit import EmitError
from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
TOOL = "cnv_belt_pick_tool"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _row(cell, program, category: str = "constant_speed"):
    chosen = [c for c in cases(cell) if c.category == category]
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def test_abb_declares_the_tool_in_a_system_module_of_its_own(cell):
    """The program module declares no tool (a new load of it would set a re-taught TCP back); the cell's system module
    does, as a persistent of the task, and every move of the program uses it. A reload is not simulated: checked on
    the text."""
    program = first(cell, "abb", "conveyor")
    files = {Path(f.name).name: f.text for f in program.files}
    assert set(files) == {"cnv_belt_pick.mod", "cnv_belt_pick_data.sys"}
    module, data = files["cnv_belt_pick.mod"], files["cnv_belt_pick_data.sys"]
    assert "tooldata" not in module
    assert data.startswith("MODULE cnv_belt_pick_data(SYSMODULE)\n")
    assert re.search(rf"^  PERS tooldata {TOOL} := \[TRUE,\n    \[\[0\.0000, 0\.0000, 150\.0000\]", data, re.M)
    moves = re.findall(r"^\s*(?:MoveL|MoveJ|MoveAbsJ) .*$", module, re.M)
    assert len(moves) > 10 and all(f", {TOOL}" in m for m in moves), [m for m in moves if TOOL not in m]
    assert _row(cell, program).mismatches == 0


def test_abb_a_signal_named_as_the_tool_is_refused(cell, tmp_path):
    text = CELL.read_text().replace('abb = "diGripClosed"', f'abb = "{TOOL}"')
    (tmp_path / "belt_pick.toml").write_text(text)
    says = rf"the conveyor program's tool and cell\.io\.feedback\.abb both map to .*{TOOL}"
    with pytest.raises(EmitError, match=says):
        render(load_cell(tmp_path / "belt_pick.toml"), ["abb"])


def test_kuka_selects_the_controllers_numbered_tool_the_cell_names(cell):
    """$TOOL = TOOL_DATA[2], $LOAD = LOAD_DATA[2] (the cell's [cell.tool] numbered), the data list saying which number
    to teach; verify's controller holds the cell's tool there, so a program that selects another number (a fresh
    controller's TOOL_DATA[3]: a null frame) fails verify."""
    program = first(cell, "kuka", "conveyor")
    src, dat = (f.text for f in program.files)
    assert "  $TOOL = TOOL_DATA[2]\n" in src and "    $LOAD = LOAD_DATA[2]\n" in src
    assert "CNV_TOOL_DATA" not in src + dat
    assert "the tool is the controller's TOOL_DATA[2] and LOAD_DATA[2]: teach the cell's" in dat
    assert _row(cell, program).mismatches == 0
    other = edited(program, lambda t: t.replace("$TOOL = TOOL_DATA[2]", "$TOOL = TOOL_DATA[3]"))
    row = _row(cell, other)
    assert row.mismatches == 1 and "position error 150.000000 mm" in row.first_mismatches[0], row.first_mismatches
