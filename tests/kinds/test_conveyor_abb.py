"""The ABB belt program on the Conveyor Tracking option as ABB's engineer reads it: the coordinated work object's
frames, leaving the belt before DropWObj, a grip that fails while tracking, the queues at the start."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.program import OUT_OF_STEP
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


def _moves_before_drops(text: str) -> list[str]:
    """The move instruction before each DropWObj after the arm first moved (the one at the start drops a connection a
    stop left, before any move)."""
    lines = [line.strip() for line in text.splitlines()]
    moves = ("MoveL ", "MoveJ ", "MoveAbsJ ")
    out, last = [], None
    for line in lines:
        if line.startswith(moves):
            last = line
        elif line.startswith("DropWObj") and last is not None:
            out.append(last)
        elif line.startswith(("PROC ", "LOCAL PROC ", "LOCAL FUNC ")):
            last = None if line.startswith("PROC main") else last
    return out


def test_the_arm_leaves_the_belt_in_a_fixed_work_object_before_it_disconnects(cell):
    """Every DropWObj once the arm has moved follows a move in a fixed work object (off the belt), as public programs
    do; the skip after a descent that reached the window's end left it at a fine point in cnv_track before."""
    text = first(cell, "abb", "conveyor").files[0].text
    before = _moves_before_drops(text)
    assert len(before) >= 2 and not [m for m in before if "cnv_track" in m], before
    off = "    MoveJ cnv_on_part(x, CNV_START, CNV_Z_MAX + CNV_DZ), cnv_travel, fine, cnv_belt_pick_tool"
    off += " \\WObj:=cnv_wobj;\n"
    mutant = text.replace(off, "")  # up in cnv_track, then DropWObj there (the program before)
    assert mutant != text and [m for m in _moves_before_drops(mutant) if "cnv_track" in m]


def test_a_grip_not_confirmed_while_tracking_leaves_the_belt_and_skips_the_part(cell):
    """The gripper silent while the arm follows the part: released, up in cnv_track, above the window's start in the
    fixed work object, DropWObj, the part skipped with a message; the program runs on to the line's stop. A program
    that stops there (connected, over a running belt, the gripper closed) fails verify's gripper_silent case."""
    program = first(cell, "abb", "conveyor")
    row = _row(cell, program, ("gripper_silent",))
    assert row.mismatches == 0, row.first_mismatches
    handler = "    IF ERRNO = ERR_WAIT_MAXTIME THEN\n      RETURN FALSE;\n"
    stops = handler.replace("RETURN FALSE;", 'cnv_stop "no feedback from the gripper in 0.5 s";')
    stopping = edited(program, lambda t: t.replace(handler, stops))
    row = _row(cell, stopping, ("gripper_silent",))
    assert row.mismatches == 1 and "did not hold" in row.first_mismatches[0], row.first_mismatches


def test_a_start_after_a_stop_before_waitwobj_empties_the_units_queue(cell):
    """A run took part 1 from the PLC (SetGO goCnvAck) and stopped before WaitWObj: its object is still in CNV1's
    queue when the program starts again from main, and the PLC presents part 2. The program pulses c1RemAllPObj at its
    start (and skips any part of the PLC's seen before then), so WaitWObj connects part 2's object; without the pulse
    it connects part 1's, whose position is not part 2's: the program stops out of step (a mismatch: no pick)."""
    one = next(c for c in cases(cell) if c.category == "constant_speed")
    first_part, second = one.parts[0], one.parts[1]
    case = replace(
        one,
        category="restart_after_ack",
        before=(replace(first_part, seq=1, seen_s=-3.0),),
        parts=(replace(second, seq=2, seen_s=2.0),),
    )
    program = first(cell, "abb", "conveyor")
    assert "    PulseDO c1RemAllPObj;\n" in program.files[0].text
    row = run_cases(cell, replace(program, row=0), [case], 600_000, False)
    assert row.mismatches == 0 and row.figures.picked == 1, row.first_mismatches
    kept = edited(program, lambda text: text.replace("    PulseDO c1RemAllPObj;\n", ""))
    row = run_cases(cell, replace(kept, row=0), [case], 600_000, False)
    # the connected object's position is not part 2's: the program drops it and stops before any grip
    assert row.mismatches == 1 and OUT_OF_STEP in row.first_mismatches[0], row.first_mismatches
