"""The wait above the belt clear of the tallest part the cell allows (z_range_mm's top + approach_dz) on every target;
the intercept down to the part's own approach height only as the part nears: a wait at the part's own height fails
verify."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor import budget
from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases
from tests.kinds.test_conveyor_programs import intercept_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
ABB_WAIT = "MoveJ cnv_on_part(x, CNV_START, {z}), cnv_travel, fine, cnv_belt_pick_tool \\WObj:=cnv_wobj;\n"
ABB_WAIT += "    y := cnv_y(seen);"
# (target, the program's text, the wait at the part's own approach height, what verify says)
OWN_HEIGHT = [
    ("kuka", "  PTP CLEAR ; wait above", "  PTP ABOVE ; wait above", "the wait for it"),
    ("ur", "cnv_on_part(x, CNV_START, CNV_Z_MAX, CNV_DZ)", "cnv_on_part(x, CNV_START, z, CNV_DZ)", "the wait for it"),
    ("abb", ABB_WAIT.format(z="CNV_Z_MAX + CNV_DZ"), ABB_WAIT.format(z="z + CNV_DZ"), "the wait for it"),
    # the intercept straight down from its wait onto the part (no stage at the part's approach height): each case fails
    # its own way
    ("kuka", "      LIN ABOVE ; down to the part's own", "      ; down to the part's own", ""),
]


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _run(cell, program):
    chosen = [c for c in cases(cell) if c.category in ("constant_speed", "gripper_silent")]
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_the_wait_is_clear_of_the_tallest_part(cell, target):
    row = _run(cell, first(cell, target, "conveyor"))
    assert row.cases == 2 and row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize(("target", "old", "new", "says"), OWN_HEIGHT)
def test_a_wait_at_the_parts_own_height_fails_verify(cell, target, old, new, says):
    program = first(cell, target, "conveyor")
    assert sum(f.text.count(old) for f in program.files) == 1
    row = _run(cell, edited(program, lambda t: t.replace(old, new)))
    assert row.mismatches == 2 and all(says in m for m in row.first_mismatches), row.first_mismatches


def test_the_timed_descent_stays_approach_dz():
    """The budget counts the descent of approach_dz and overtravel_mm only (the way down from the clear height is the
    first stage's): 2.90 mm of the gripper's 3 mm at 40 mm/s."""
    assert budget.total_mm(load_cell(CELL), "kuka") == pytest.approx(2.905, abs=1e-3)


# (target, the program's text, the lift with the part held that puts the gripper's tip, not the part's bottom, at the
# clear height: an 80 mm part hangs 60 mm above the belt, below the tallest part) on the bundled cell (ABB native) and,
# with ABB intercepting, ABB's intercept
UR_LIFT = "movel(cnv_on_part(x, y, {z}), a=1.200, v=0.2500)\n    stop_conveyor_tracking()\n"
ABB_LIFT = "MoveL {pose}, cnv_work, cnv_zone, cnv_belt_pick_tool \\WObj:=cnv_wobj;\n    MoveJ cnv_place_above"
LOW_LIFT = [
    ("ur", UR_LIFT.format(z="z, CNV_Z_MAX + CNV_DZ"), UR_LIFT.format(z="CNV_Z_MAX, CNV_DZ")),
    ("kuka", "  LIN LIFTED C_DIS\n", "  LIN CLEAR C_DIS\n"),
    ("abb", "    above.trans := [x, 0, z + CNV_Z_MAX + CNV_DZ];\n", "    above.trans := [x, 0, CNV_Z_MAX + CNV_DZ];\n"),
    (
        "abb intercept",
        ABB_LIFT.format(pose="cnv_on_part(x, y, z + CNV_Z_MAX + CNV_DZ)"),
        ABB_LIFT.format(pose="cnv_on_part(x, y, CNV_Z_MAX + CNV_DZ)"),
    ),
]


def _cell_for(target: str, tmp_path):
    """The bundled cell, or with ABB intercepting (a controller without the Conveyor Tracking option)."""
    return intercept_cell(tmp_path) if target.endswith("intercept") else load_cell(CELL)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb", "abb intercept"])
def test_the_part_held_is_lifted_to_the_clear_height(tmp_path, target):
    """After the grip the arm lifts the part straight up until the part's bottom is at the height the empty gripper
    waits at (z_range_mm's top + approach_dz): the gripper's tip there would leave a tall part held hanging lower than
    the tallest part still on the belt."""
    cell = _cell_for(target, tmp_path)
    program = first(cell, target.split()[0], "conveyor")
    chosen = [c for c in cases(cell) if c.category == "constant_speed"]
    row = run_cases(cell, replace(program, row=0), chosen, 600_000, False)
    assert row.mismatches == 0 and row.figures.picked >= 2, row.first_mismatches


@pytest.mark.parametrize(("target", "old", "new"), LOW_LIFT)
def test_a_lift_of_the_tip_only_to_the_clear_height_fails_verify(tmp_path, target, old, new):
    cell = _cell_for(target, tmp_path)
    program = first(cell, target.split()[0], "conveyor")
    assert sum(f.text.count(old) for f in program.files) == 1
    chosen = [c for c in cases(cell) if c.category == "constant_speed"]
    row = run_cases(cell, replace(edited(program, lambda t: t.replace(old, new)), row=0), chosen, 600_000, True)
    assert row.mismatches == 1 and "the lift to the clear height" in row.first_mismatches[0], row.first_mismatches
