"""The ABB belt program on the Conveyor Tracking option as ABB's engineer reads it: the coordinated work object's
frames, leaving the belt before DropWObj, a grip that fails while tracking, the queues at the start."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.verify import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
IDENTITY = "[[0, 0, 0], [1, 0, 0, 0]]"
TURN = "[[0.0000, 0.0000, 0.0000], [0.707106781, 0.000000000, 0.000000000, -0.707106781]]"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _row(cell, program, categories: tuple[str, ...]):
    chosen = [c for c in cases(cell) if c.category in categories]
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def test_the_belts_turn_is_in_the_object_frame_of_the_coordinated_work_object(cell):
    """ufprog FALSE: the controller takes the user frame from the unit's system parameters and ignores the program's
    uframe. The program keeps its uframe the identity and turns the unit's x (the travel) into the belt's y in the
    oframe; the same turn written in the uframe (the oframe the identity) is lost on the controller: the arm comes
    down 90 degrees off the belt's axes, and verify refuses it."""
    program = first(cell, "abb", "conveyor")
    text = program.files[0].text
    declared = f'TASK PERS wobjdata cnv_track := [FALSE, FALSE, "CNV1",\n    {IDENTITY},\n    {TURN}];'
    assert declared in text
    assert _row(cell, program, ("constant_speed",)).mismatches == 0
    old = f'TASK PERS wobjdata cnv_track := [FALSE, FALSE, "CNV1",\n    {TURN},\n    {IDENTITY}];'
    in_uframe = edited(program, lambda t: t.replace(declared, old))
    assert old in in_uframe.files[0].text
    row = _row(cell, in_uframe, ("constant_speed",))
    assert row.mismatches == 1 and "gripped" in row.first_mismatches[0], row.first_mismatches
