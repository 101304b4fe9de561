"""The simulated gripper holds and releases grip_s after its output (the cell's 45-55 ms, drawn per case), as a
vacuum gripper does: a program that lifts after a fixed short wait instead of the gripper's feedback fails verify on
every target, which a gripper answering in 20 ms let through."""

from __future__ import annotations

from pathlib import Path

import pytest
from support.programs import edited, first, verify_one

from codegen.model.cell import load_cell
from codegen.sim.gripper import Gripper

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
HOLD_WAIT = {  # the wait for the grip's feedback, and a fixed 20 ms in its place
    "abb": (
        "    WaitDI diGripClosed, 1 \\MaxTime:=IO_TIMEOUT;\n    ! confirmed: the payload now\n    GripLoad cnv_part;\n"
        "    RETURN TRUE;",
        "    WaitTime 0.02;\n    ! confirmed: the payload now\n    GripLoad cnv_part;\n    RETURN TRUE;",
    ),
    "ur": (
        "    while get_standard_digital_in(1) != True:\n      if polls >= IO_POLLS:\n        return False\n      end\n"
        "      sleep(0.05)\n      polls = polls + 1\n    end\n",
        "    sleep(0.02)\n",
    ),
    "kuka": (
        "  WHILE $IN[18] <> TRUE\n    IF POLLS >= CNV_IO_POLLS THEN\n      RETURN FALSE\n    ENDIF\n    WAIT SEC 0.05\n"
        "    POLLS = POLLS + 1\n  ENDWHILE\n  $LOAD = CNV_LOAD_HELD",
        "  WAIT SEC 0.02\n  $LOAD = CNV_LOAD_HELD",
    ),
}


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.mark.parametrize("target", ["abb", "ur", "kuka"])
def test_a_lift_on_a_fixed_wait_before_the_hold_fails_verify(cell, target):
    program = first(cell, target, "conveyor")
    old, new = HOLD_WAIT[target]
    assert old in program.files[0].text
    mutant = edited(program, lambda text: text.replace(old, new, 1), "no_hold_wait")
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0, f"verify missed on {target}: a lift 20 ms after the grip's output"
    assert any("the gripper held the part" in m for m in row.first_mismatches), row.first_mismatches


def test_the_late_gripper_answers_after_its_time_and_records_it():
    """A gripper 'late' by 50 ms: its feedback on 50 ms after the output, recorded as a change."""

    class Clock:
        clock = 0.0
        signals: dict = {}

    machine = Clock()
    gripper = Gripper("out", "in", True, "late", late_s=0.05)
    machine.signals = {"out": True}
    gripper.on_wait(machine, "here")
    assert gripper.next_time(machine) == pytest.approx(0.05) and "in" not in machine.signals
    machine.clock = 0.05
    assert gripper.on_wait(machine, "here") and machine.signals["in"] is True
    assert gripper.changes == [(pytest.approx(0.05), True)]
