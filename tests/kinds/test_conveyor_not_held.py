"""A grip not confirmed while the arm is on a part on the running belt, on every target: released, up off the part, the
part skipped with a message, on to the next; the old halt at the part (and a lift left out) fail verify."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.verify import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
GRASP_TIMEOUT = "    IF POLLS >= CNV_IO_POLLS THEN\n"
HALT_KUKA = GRASP_TIMEOUT + '      CNV_MSG.MSG_TXT[] = "no feedback from the gripper in 0.5 s"\n      CNV_HALT()\n'
HALT_UR = '        stop_conveyor_tracking()\n        cnv_stop("no feedback from the gripper in 0.5 s")\n'
HALTED = "did not hold: stopped on the running belt"
LIFT = "      movel(cnv_on_part(x, y, CNV_Z_MAX, CNV_DZ), a=1.200, v=0.2500)\n"
UNTRACK = "      stop_conveyor_tracking()\n      set_standard_digital_out(1, False)   # back at the clear height\n"
SKIP = '      textmsg(str_cat("conveyor: the gripper'
# (target, the program's text, the broken text, what verify says): the halt at the part the programs had, and a release
# without the lift off the part (KUKA), the lift after the tracking stopped (UR: the arm no longer follows the part)
BROKEN = [
    ("kuka", GRASP_TIMEOUT + "      RETURN FALSE\n", HALT_KUKA + "      RETURN FALSE\n", HALTED),
    ("ur", "        return False\n", HALT_UR, HALTED),
    ("kuka", "    $OUT[17] = FALSE\n    LIN CLEAR\n", "    $OUT[17] = FALSE\n", "not both on the part"),
    ("ur", LIFT + UNTRACK + SKIP, UNTRACK + LIFT + SKIP, "the lift off it, released"),
]


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _silent(cell, program):
    chosen = [c for c in cases(cell) if c.category == "gripper_silent"]
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_grip_not_confirmed_on_the_belt_is_released_lifted_off_and_skipped(cell, target):
    """The gripper silent: no stop, the part skipped with a message, the program on to the line's stop (every
    target the same)."""
    row = _silent(cell, first(cell, target, "conveyor"))
    assert row.cases == 1 and row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize(("target", "old", "new", "says"), BROKEN)
def test_a_halt_at_the_part_or_a_missing_lift_fails_verify(cell, target, old, new, says):
    program = first(cell, target, "conveyor")
    assert program.files[0].text.count(old) == 1
    broken = edited(program, lambda t: t.replace(old, new))
    row = _silent(cell, broken)
    assert row.mismatches == 1 and says in row.first_mismatches[0], row.first_mismatches
