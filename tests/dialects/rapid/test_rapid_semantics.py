"""RAPID controller semantics: move timing, waits, ERROR handlers, operator messages, LOCAL declarations."""

from __future__ import annotations

import pytest

from codegen.dialects.core.machine import Machine
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.interpreter import load

TARGET = "CONST robtarget {name} := [[{x}, 0, 500], [1, 0, 0, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];"
TARGETS = "\n".join(TARGET.format(name=n, x=x) for n, x in (("p0", 0), ("p400", 400), ("p1000", 1000)))


def mod(body: str, decls: str = "", routines: str = "") -> str:
    return f"MODULE T\n{TARGETS}\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


def run(body: str, decls: str = "", routines: str = "", devices=()):
    return load(mod(body, decls, routines), "t.mod").run({}, devices=devices)


class Clock:
    """A device that records the program's clock, and whether the arm still moves, whenever the program waits."""

    def __init__(self) -> None:
        self.seen: list[tuple[float, bool]] = []

    def on_wait(self, machine: Machine, where: str) -> bool:
        self.seen.append((round(machine.clock, 6), machine.moving))
        return False

    def next_time(self, machine: Machine) -> None:
        return None


class SetsAt:
    """A device that sets a num variable to 1 at a given time."""

    def __init__(self, name: str, at: float) -> None:
        self.name, self.at = name, at

    def on_wait(self, machine: Machine, where: str) -> bool:
        if machine.clock >= self.at and machine.read_variable(self.name) != 1:
            return machine.write_variable(self.name, 1)
        return False

    def next_time(self, machine: Machine) -> float | None:
        return self.at if machine.read_variable(self.name) != 1 else None


START = "MoveL p0, v200, fine, tool0;\nWaitTime 0;"  # the arm at p0, the clock marked


def clock_after(body: str, decls: str = "") -> tuple[float, bool]:
    """The clock (and whether the arm moves) at a WaitTime 0 after body, from the mark after START
    (the first move's time is not known: it starts wherever the arm stands)."""
    clock = Clock()
    run(f"{START}\n{body}\nWaitTime 0;", decls, devices=[clock])
    start, _moving = clock.seen[0]
    end, moving = clock.seen[-1]
    return round(end - start, 6), moving


# --- 1. move timing ------------------------------------------------------------------------------


def test_a_fine_move_takes_its_distance_over_the_speeddata_tcp_speed():
    assert clock_after("MoveL p400, v200, fine, tool0;") == (2.0, False)
    assert clock_after("MoveJ p400, v100, fine, tool0;\nMoveJ p0, v400, fine, tool0;") == (5.0, False)


def test_a_fly_by_zone_lets_the_program_run_ahead_of_the_arm():
    assert clock_after("MoveL p400, v200, z10, tool0;") == (0.0, True)
    # the next move starts when the arm ends the one before: a fine one after a fly-by one
    assert clock_after("MoveL p400, v200, z0, tool0;\nMoveL p0, v200, fine, tool0;") == (4.0, False)
    assert clock_after("MoveL p400, v200, z200, tool0;\nMoveL p0, v200, z50, tool0;") == (0.0, True)


def test_vmax_speeddata_records_zonedata_records_and_the_v_argument():
    assert clock_after("MoveL p1000, vmax, fine, tool0;") == (0.2, False)
    decls = "VAR speeddata slow := [100, 500, 5000, 1000];\nVAR zonedata fly := [FALSE, 10, 15, 15, 1.5, 15, 1.5];"
    decls += "\nVAR zonedata stop := [TRUE, 0, 0, 0, 0, 0, 0];"
    assert clock_after("MoveL p400, slow, stop, tool0;", decls) == (4.0, False)
    assert clock_after("MoveL p400, slow, fly, tool0;", decls) == (0.0, True)
    assert clock_after("MoveL p400, v200\\V:=50, fine, tool0;") == (8.0, False)


def test_every_move_instruction_needs_a_speed_and_a_zone():
    joints = "CONST jointtarget j := [[0, 0, 0, 0, 30, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];"
    with pytest.raises(RunError, match=r"t\.mod:\d+:1: the move's TCP speed must be above 0 mm/s"):
        run("MoveAbsJ j, stopped, fine, tool0;", joints + "\nCONST speeddata stopped := [0, 500, 5000, 1000];")
    with pytest.raises(RunError, match=r"t\.mod:\d+:1: the move's zone is not a zonedata"):
        run("MoveJ p0, v100, 5, tool0;")


# --- 2. waits ------------------------------------------------------------------------------------


def test_wait_until_max_time_with_a_time_flag_sets_it_and_goes_on():
    clock = Clock()
    body = 'WaitUntil x = 1 \\MaxTime:=1.5 \\TimeFlag:=late;\nIF late TPWrite "late";\nWaitTime 0;'
    trace = run(body, "VAR num x := 0;\nVAR bool late := FALSE;", devices=[clock])
    assert trace.messages == ["late"] and not trace.halted
    assert clock.seen[-1] == (1.5, False)


def test_wait_until_time_flag_is_false_when_the_condition_comes_true():
    body = 'WaitUntil x = 1 \\MaxTime:=5 \\TimeFlag:=late;\nIF NOT late TPWrite "in time";'
    trace = run(body, "VAR num x := 0;\nVAR bool late := TRUE;", devices=[SetsAt("x", 2.0)])
    assert trace.messages == ["in time"]


def test_wait_until_max_time_without_a_handler_stops_the_program_with_err_wait_maxtime():
    trace = run('WaitUntil x = 1 \\MaxTime:=2;\nTPWrite "never";', "VAR num x := 0;")
    assert trace.halted and trace.messages == []
    assert trace.halt_message.startswith("ERR_WAIT_MAXTIME: t.mod:")


def test_wait_until_in_pos_waits_for_the_arm_first():
    body = "MoveL p400, v200, z10, tool0;\nWaitUntil \\InPos, TRUE;"
    assert clock_after(body) == (2.0, False)
    with pytest.raises(RunError, match=r"PollRate below 0\.04 s"):
        run("WaitUntil TRUE \\PollRate:=0.01;")


def test_wait_time_sleeps_and_in_pos_waits_for_the_arm_first():
    assert clock_after("WaitTime 1.5;") == (1.5, False)
    moves = "MoveL p400, v200, z10, tool0;"
    assert clock_after(f"{moves}\nWaitTime 1;") == (1.0, True)
    assert clock_after(f"{moves}\nWaitTime \\InPos, 1;") == (3.0, False)
    with pytest.raises(RunError, match=r"t\.mod:\d+:1: WaitTime -1 s"):
        run("WaitTime -1;")


def test_wait_rob_waits_until_the_arm_stands_still():
    moves = "MoveL p400, v200, z10, tool0;"
    assert clock_after(f"{moves}\nWaitRob \\InPos;") == (2.0, False)
    assert clock_after(f"{moves}\nWaitRob \\ZeroSpeed;") == (2.0, False)
    with pytest.raises(RunError, match="WaitRob takes"):
        run("WaitRob;")


# --- 3. error handlers ---------------------------------------------------------------------------

COUNT = "VAR num n := 0;\nVAR num x := 0;"


def test_retry_runs_the_instruction_that_raised_the_error_again():
    body = 'WaitUntil x = 1 \\MaxTime:=1;\nTPWrite "done" \\Num:=n;\nERROR\n  n := n + 1;\n  IF n = 2 x := 1;\n  RETRY;'
    trace = run(body, COUNT)
    assert trace.messages == ["done2"] and not trace.halted


def test_retry_stops_the_program_after_no_of_retry_recoveries():
    body = 'RAISE 7;\nTPWrite "never";\nERROR\n  n := n + 1;\n  TPWrite "retry" \\Num:=n;\n  RETRY;'
    trace = run(body, COUNT)
    assert trace.messages == [f"retry{i}" for i in range(1, 6)]
    assert trace.halted and trace.halt_message.startswith("ERRNO 7: ") and "No Of Retry = 4" in trace.halt_message


def test_trynext_goes_on_after_the_instruction_even_inside_a_loop():
    body = (
        'FOR i FROM 1 TO 3 DO\n  IF i = 2 THEN\n    RAISE 5;\n  ENDIF\n  TPWrite "i" \\Num:=i;\nENDFOR\n'
        'ERROR\n  TPWrite "errno" \\Num:=ERRNO;\n  TRYNEXT;'
    )
    assert run(body).messages == ["i1", "errno5", "i2", "i3"]


def test_a_function_handler_returns_a_value_for_a_division_by_zero():
    routines = (
        "FUNC num safediv(num a, num b)\n  RETURN a / b;\nERROR\n  IF ERRNO = ERR_DIVZERO THEN\n"
        '    TPWrite "zero";\n    RETURN a;\n  ENDIF\n  RAISE;\nENDFUNC'
    )
    trace = run('TPWrite "q" \\Num:=safediv(6, 3);\nTPWrite "q" \\Num:=safediv(6, 0);', routines=routines)
    assert trace.messages == ["q2", "zero", "q6"]


def test_an_error_propagates_to_the_callers_handler_and_retry_calls_again():
    routines = 'PROC inner()\n  n := n + 1;\n  IF n < 3 RAISE 9;\n  TPWrite "inner ok";\nENDPROC'
    body = 'inner;\nTPWrite "calls" \\Num:=n;\nERROR\n  TPWrite "main errno" \\Num:=ERRNO;\n  RETRY;'
    trace = run(body, COUNT, routines)
    assert trace.messages == ["main errno9", "main errno9", "inner ok", "calls3"]


def test_raise_in_a_handler_passes_the_error_on_and_a_new_number_replaces_it():
    routines = (
        'PROC inner()\n  RAISE 4;\nERROR\n  TPWrite "inner";\n  RAISE;\nENDPROC\n'
        "PROC renumber()\n  RAISE 4;\nERROR\n  RAISE 12;\nENDPROC"
    )
    body = 'inner;\nrenumber;\nTPWrite "end";\nERROR\n  TPWrite "main" \\Num:=ERRNO;\n  TRYNEXT;'
    assert run(body, routines=routines).messages == ["inner", "main4", "main12", "end"]


def test_the_end_of_a_handler_returns_from_the_routine():
    routines = 'PROC inner()\n  RAISE 3;\n  TPWrite "not here";\nERROR\n  TPWrite "handled";\nENDPROC'
    assert run('inner;\nTPWrite "back";', routines=routines).messages == ["handled", "back"]
    func = 'FUNC num f()\n  RAISE 3;\nERROR\n  TPWrite "handled";\nENDFUNC'
    with pytest.raises(RunError, match="function f ended without RETURN"):
        run("x := f();", COUNT, func)


def test_a_handler_with_numbers_takes_only_those():
    routines = 'PROC inner(num e)\n  RAISE e;\nERROR (3, 4)\n  TPWrite "inner" \\Num:=ERRNO;\nENDPROC'
    body = 'inner 3;\ninner 8;\nTPWrite "end";\nERROR\n  TPWrite "main" \\Num:=ERRNO;\n  TRYNEXT;'
    assert run(body, routines=routines).messages == ["inner3", "main8", "end"]


def test_an_unhandled_error_stops_the_program_naming_it():
    trace = run('RAISE ERR_MINE;\nTPWrite "never";', "CONST errnum ERR_MINE := 7;")
    assert trace.halted and trace.messages == []
    assert trace.halt_message.startswith("ERR_MINE: t.mod:") and trace.halt_message.endswith("RAISE ERR_MINE")


def test_an_error_inside_a_handler_cannot_be_recovered():
    routines = "PROC inner()\n  RAISE 3;\nERROR\n  x := 1 / 0;\nENDPROC"
    with pytest.raises(RunError, match=r"t\.mod:\d+:3: division by zero"):
        run('inner;\nERROR\n  TPWrite "never";\n  TRYNEXT;', COUNT, routines)
    # an unhandled division by zero stays a program error, as before
    with pytest.raises(RunError, match=r"t\.mod:\d+:1: division by zero"):
        run("x := 1 / 0;", COUNT)


def test_raise_numbers_outside_1_to_90_are_err_illraise_unless_booked():
    body = 'RAISE 91;\nERROR\n  IF ERRNO = ERR_ILLRAISE TPWrite "illegal";\n  TRYNEXT;'
    assert run(body).messages == ["illegal"]
    decls = "VAR errnum ERR_OWN := -1;"
    body = 'BookErrNo ERR_OWN;\nRAISE ERR_OWN;\nERROR\n  IF ERRNO = ERR_OWN TPWrite "own";\n  TRYNEXT;'
    assert run(body, decls).messages == ["own"]


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("RETRY;", "RETRY outside an error handler"),
        ("TRYNEXT;", "TRYNEXT outside an error handler"),
        ("RAISE;", "RAISE without an error number outside an error handler"),
    ],
)
def test_handler_instructions_outside_a_handler_are_refused(body, message):
    with pytest.raises(RunError, match=rf"t\.mod:\d+:1: {message}"):
        load(mod(body), "t.mod")


# --- 4. messages ---------------------------------------------------------------------------------


def test_err_write_records_its_reason_and_stop_shows_it():
    trace = run('ErrWrite "Gripper", "no part" \\RL2:="check the feeder";\nStop;\nTPWrite "resumed";')
    assert trace.halted and trace.halt_message == "no part"
    assert trace.messages == ["no part", "resumed"]
    assert run('ErrWrite \\W, "Gripper", "slow";').messages == ["slow"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (f'"{"h" * 47}", "r"', "ErrWrite header has 47 characters, at most 46"),
        (f'"h", "r" \\RL2:="{"x" * 40}" + "{"x" * 41}"', r"ErrWrite \\RL2 has 81 characters, at most 80"),
        (
            '"h", "{0}" \\RL2:="{0}" \\RL3:="{1}"'.format("x" * 80, "x" * 36),
            "ErrWrite reason lines have 196 characters, at most 195",
        ),
        ('"h"', "ErrWrite takes a header and a reason"),
    ],
)
def test_err_write_limits_name_the_line(args, message):
    with pytest.raises(RunError, match=rf"t\.mod:\d+:1: {message}"):
        run(f"ErrWrite {args};")


def test_ui_msg_box_records_its_line_and_the_operator_presses_the_first_button():
    decls = "VAR btnres answer := 0;"
    body = 'UIMsgBox \\Header:="Cell", "Part missing" \\Buttons:=btnYesNo \\Icon:=iconError \\Result:=answer;'
    body += '\nIF answer = resYes TPWrite "yes";'
    assert run(body, decls).messages == ["Part missing", "yes"]
    assert run('UIMsgBox "Ready";').messages == ["Ready"]
    with pytest.raises(RunError, match="waits forever"):
        run('UIMsgBox "Stuck" \\Buttons:=btnNone;')


def test_exit_ends_the_program():
    trace = run('TPWrite "bye";\nEXIT;\nTPWrite "never";')
    assert trace.halted and trace.messages == ["bye"]


# --- 5. LOCAL and module data --------------------------------------------------------------------


def test_local_routines_and_data_behave_as_the_others():
    decls = (
        "LOCAL VAR num count := 1;\nLOCAL CONST num incr := 2;\nLOCAL PERS num kept := 5;\n"
        'PERS wobjdata table := [FALSE, TRUE, "", [[400, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];\n'
        "PERS tooldata gripper := [TRUE, [[0, 0, 100], [1, 0, 0, 0]], [1, [0, 0, 50], [1, 0, 0, 0], 0, 0, 0]];"
    )
    routines = (
        "LOCAL PROC bump()\n  count := count + incr;\nENDPROC\n"
        "LOCAL FUNC num twice(num a)\n  RETURN 2 * a;\nENDFUNC\n"
        "LOCAL TRAP never\n  count := 0;\nERROR\n  RETURN;\nENDTRAP"
    )
    body = 'bump;\nTPWrite "c" \\Num:=twice(count) + kept;\nMoveL p0, v100, fine, gripper \\WObj:=table;'
    trace = run(body, decls, routines)
    assert trace.messages == ["c11"]
    assert trace.moves[0].tcp2base[:3, 3].tolist() == [400.0, 0.0, 500.0]
    assert trace.moves[0].settings["load"] == (1.0, 0.0, 0.0, 50.0, *(0.0,) * 6)


def test_offs_moves_a_target_in_its_work_object():
    """Offs adds the offsets in the object frame: with a work object turned 90 deg about z, +x of the offset
    is +y of the base; orientation, robconf and external axes stay."""
    decls = (
        'PERS wobjdata turned := [FALSE, TRUE, "", [[100, 0, 0], [0.70710678, 0, 0, 0.70710678]], '
        "[[0, 0, 0], [1, 0, 0, 0]]];\nVAR robtarget moved;"
    )
    body = (
        "moved := Offs(p400, 10, 20, 30);\n"
        'TPWrite "" \\Num:=moved.trans.x + moved.trans.y + moved.trans.z;\n'
        'IF moved.rot = p400.rot AND moved.robconf = p400.robconf AND moved.extax = p400.extax TPWrite "kept";\n'
        "MoveL moved, v100, fine, tool0 \\WObj:=turned;"
    )
    trace = run(body, decls)
    assert trace.messages == [str(410 + 20 + 530), "kept"]
    assert [round(v, 3) for v in trace.moves[0].tcp2base[:3, 3].tolist()] == [80.0, 410.0, 530.0]
    with pytest.raises(RunError, match="Offs takes"):
        run("moved := Offs(p400, 10, 20);", "VAR robtarget moved;")


def test_only_persistent_data_takes_an_input():
    """A run starts at main: VAR data gets its initial value, only PERS data keeps one from before the run."""
    program = load(mod('TPWrite "" \\Num:=kept + count;', "PERS num kept := 1;\nVAR num count := 10;"), "t.mod")
    assert program.run({"kept": 5}).messages == ["15"]
    with pytest.raises(RunError, match="VAR data gets its initial value"):
        program.run({"count": 5})
