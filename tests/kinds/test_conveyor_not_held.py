"""A grip not confirmed while the arm is on a part on the running belt, on every target: released, its feedback awaited
off, up off the part, the part skipped with a message, on to the next; a halt at the part, a lift left out and a lift
before the feedback drops fail verify."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
GRASP_TIMEOUT = "  WHILE $IN[18] <> TRUE\n    IF POLLS >= CNV_IO_POLLS THEN\n"
HOLD_UR = "    while get_standard_digital_in(1) != True:\n      if polls >= IO_POLLS:\n"
HALT_KUKA = GRASP_TIMEOUT + '      CNV_MSG.MSG_TXT[] = "no feedback from the gripper in 0.5 s"\n      CNV_HALT()\n'
HALT_UR = '        stop_conveyor_tracking()\n        cnv_stop("no feedback from the gripper in 0.5 s")\n'
HALTED = "did not hold: stopped on the running belt"
LIFT = "      movel(cnv_on_part(x, y, CNV_Z_MAX, CNV_DZ), a=1.200, v=0.2500)\n"
UNTRACK = "      stop_conveyor_tracking()\n      set_standard_digital_out(1, False)   # back at the clear height\n"
LET_GO = "      cnv_opened = cnv_let_go()\n"
# (target, the program's text, the broken text, what verify says): the halt at the part the programs had, and a release
# without the lift off the part (KUKA), the lift after the tracking stopped (UR: the arm no longer follows the part)
BROKEN = [
    ("kuka", GRASP_TIMEOUT + "      RETURN FALSE\n", HALT_KUKA + "      RETURN FALSE\n", HALTED),
    ("ur", HOLD_UR + "        return False\n", HOLD_UR + HALT_UR, HALTED),
    (  # the lift after the failed grip (the stop while the belt stands has a LIN CLEAR of its own, deeper in)
        "kuka",
        "    LIN CLEAR\n    $OUT[18] = FALSE ; back at the clear height\n    IF NOT OPENED",
        "    $OUT[18] = FALSE ; back at the clear height\n    IF NOT OPENED",
        "not both on the part",
    ),
    ("ur", LET_GO + LIFT + UNTRACK, LET_GO + UNTRACK + LIFT, "the lift off it, released"),
]
# the release of a part not held without waiting for the feedback to drop (the output alone, then the lift): the cup
# sealed on the part as the program gave up carries it up
NO_WAIT = [
    ("ur", LET_GO, "      set_standard_digital_out(0, False)\n      cnv_opened = True\n"),
    ("kuka", "    OPENED = CNV_LET_GO()", "    $OUT[17] = FALSE\n    OPENED = TRUE"),
    ("abb", "      opened := cnv_let_go();\n", "      SetDO doGripClose, 0;\n      opened := TRUE;\n"),
]


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _silent(cell, program, category: str = "gripper_silent"):
    chosen = [c for c in cases(cell) if c.category == category]
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


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_cup_sealed_as_the_grip_is_given_up_is_let_go_before_the_lift(cell, target):
    """The cup seals on the part only as the program gives up (its feedback on from the release until the vacuum has
    decayed, the case's grip_s later): every target waits for the feedback to drop before it lifts."""
    case = next(c for c in cases(cell) if c.category == "gripper_sealed")
    pick = cell.sections["conveyor"].pick
    assert case.gripper == "sealed" and pick.grip_s[0] <= case.grip_s <= pick.grip_s[1]
    row = _silent(cell, first(cell, target, "conveyor"), "gripper_sealed")
    assert row.cases == 1 and row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize(("target", "old", "new"), NO_WAIT)
def test_a_lift_before_the_feedback_drops_carries_the_part_up(cell, target, old, new):
    program = first(cell, target, "conveyor")
    assert sum(f.text.count(old) for f in program.files) == 1
    broken = edited(program, lambda t: t.replace(old, new))
    row = _silent(cell, broken, "gripper_sealed")
    assert row.mismatches == 1 and "the gripper let go at" in row.first_mismatches[0], row.first_mismatches
    assert _silent(cell, broken).mismatches == 0  # a gripper that never held: nothing to wait for
