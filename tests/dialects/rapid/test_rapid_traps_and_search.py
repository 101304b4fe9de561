"""RAPID's interrupts (ISignalDI, TRAP), SearchL and their misuse, in the interpreter."""

from __future__ import annotations

import math

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.interpreter import load
from codegen.model.cell import load_cell
from codegen.robot.expect import arm_of

CELL = "codegen/examples/laser/laser_tcp.toml"
CYCLE = 0.004
EXT = "[9E9, 9E9, 9E9, 9E9, 9E9, 9E9]"
HEAD = f"""VAR intnum ino;
VAR num n := 0;
VAR num xs{{8}};
VAR num ys{{8}};
VAR num lv{{8}};
PERS tooldata t1 := [TRUE, [[0, 0, 0], [1, 0, 0, 0]], [1, [0, 0, 0], [1, 0, 0, 0], 0, 0, 0]];
CONST robtarget p0 := [[0, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], {EXT}];
CONST robtarget p20 := [[20, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], {EXT}];
"""
TRAP = """TRAP tr
  VAR robtarget q;
  q := CRobT(\\Tool:=t1 \\WObj:=wobj0);
  n := n + 1;
  xs{n} := q.trans.x;
  ys{n} := q.trans.y;
  lv{n} := DInput(diA);
ENDTRAP
"""


def mod(body: str, decls: str = "", routines: str = TRAP) -> str:
    return f"MODULE T\n{HEAD}{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


class Gate:
    """Input diA on while the flange's x (or y) is past `at` (tool t1: the TCP is the flange)."""

    def __init__(self, at: float = 10.03, axis: int = 0) -> None:
        self.switches = frozenset({"diA"})
        self.at, self.axis = at, axis

    def on_wait(self, machine, where):
        return False

    def switch(self, name, t, flange2base):
        if name != "diA":
            return None
        return False if flange2base is None else bool(flange2base[self.axis, 3] > self.at)


def run(body: str, decls: str = "", routines: str = TRAP, watch: bool = True, gate=None):
    """The program against the gate; the first move (from p0's unknown start) takes 1 s."""
    program = load(mod(body, decls, routines), "t.mod")
    devices = (gate or Gate(),) if watch else ()
    return program.run({}, devices=devices, signal_cycle_s=CYCLE if watch else None, keep=("n", "xs", "ys", "lv"))


def kept(trace, name: str, count: int | None = None) -> list[float]:
    values = [float(v) for v in trace.kept[name]]
    return values[: int(trace.kept["n"])] if count is None else values[:count]


OUT_AND_BACK = """MoveL p0, v100, fine, t1;
CONNECT ino WITH tr;
ISignalDI diA, {trigger}, ino;
MoveL p20, v10, fine, t1;
MoveL p0, v10, fine, t1;
IDelete ino;
MoveL p20, v10, fine, t1;"""


# --- interrupts ---------------------------------------------------------------------------------------


def test_a_trap_runs_at_the_first_cycle_after_each_edge_with_the_tcp_there():
    """From x = 0 to 20 mm and back at 10 mm/s, the gate at x = 10.03: the controller sees the rising edge at
    2.004 s (x = 10.04, the first 4 ms cycle past it), the falling one at 4.000 s (x = 10.00); CRobT in the
    TRAP reads the TCP at that cycle, DInput the new value. After IDelete the third pass runs no TRAP."""
    trace = run(OUT_AND_BACK.format(trigger=2))
    assert not trace.halted
    assert kept(trace, "xs") == pytest.approx([10.04, 10.0], abs=1e-4)
    assert kept(trace, "lv") == [1.0, 0.0]


@pytest.mark.parametrize(("trigger", "xs", "level"), [(1, [10.04], 1.0), (0, [10.0], 0.0)])
def test_trigger_value_1_is_the_rising_edge_and_0_the_falling(trigger, xs, level):
    trace = run(OUT_AND_BACK.format(trigger=trigger))
    assert kept(trace, "xs") == pytest.approx(xs, abs=1e-4)
    assert kept(trace, "lv") == [level]


def test_without_a_switching_device_no_interrupt_comes():
    """No device switches inputs with the motion (no watching): the program runs, no TRAP."""
    trace = run(OUT_AND_BACK.format(trigger=2), watch=False)
    assert not trace.halted and int(trace.kept["n"]) == 0


def test_single_fires_once_and_idelete_before_the_arm_arrives_drops_the_later_edges():
    """\\Single: only the first edge. A fly-by move (the program runs ahead): IDelete before the arm gets
    past the gate drops that edge; the edges before the clock still run."""
    single = OUT_AND_BACK.format(trigger=2).replace("ISignalDI diA", "ISignalDI \\Single, diA")
    assert kept(run(single), "xs") == pytest.approx([10.04], abs=1e-4)
    ahead = """MoveL p0, v100, fine, t1;
CONNECT ino WITH tr;
ISignalDI diA, 2, ino;
MoveL p20, v10, z10, t1;
IDelete ino;
WaitRob \\InPos;"""
    trace = run(ahead)
    assert int(trace.kept["n"]) == 0 and not trace.halted


def test_a_circle_s_edge_is_seen_on_the_arc():
    """MoveC from (10, 0) through (0, 10) to (-10, 0) at 10 mm/s: pi s (the arc's length over v_tcp); the gate
    y > 5 switches at 30 deg, 0.5236 s into the arc: seen at the cycle 0.524 s, the TCP at 0.524 rad."""
    at = "[1, 0, 0, 0], [0, 0, 0, 0], " + EXT
    body = f"""MoveL [[10, 0, 0], {at}], v100, fine, t1;
CONNECT ino WITH tr;
ISignalDI diA, 1, ino;
MoveC [[0, 10, 0], {at}], [[-10, 0, 0], {at}], v10, fine, t1;
IDelete ino;"""
    trace = run(body, gate=Gate(5.0, axis=1))
    assert trace.moves[-1].end_time - trace.moves[-2].end_time == pytest.approx(math.pi, abs=1e-6)
    angle = 131 * CYCLE
    assert kept(trace, "xs") == pytest.approx([10 * math.cos(angle)], abs=1e-3)
    assert kept(trace, "ys") == pytest.approx([10 * math.sin(angle)], abs=1e-3)
    assert trace.moves[-1].tcp2base[:3, 3] == pytest.approx([-10, 0, 0])


def test_crobt_standing_gives_the_pose_and_configuration_a_joint_move_takes_back():
    """After MoveAbsJ home (IRB 1600): CRobT's robtarget, robconf included, is where a MoveJ with ConfJ on goes
    back to the same joints."""
    cell = load_cell(CELL)
    body = """MoveAbsJ h, v100, fine, t1;
p := CRobT(\\Tool:=t1 \\WObj:=wobj0);
MoveJ p, v100, fine, t1;"""
    decls = "CONST jointtarget h := [[10, 20, -10, 30, 60, -40], " + EXT + "];\nVAR robtarget p;"
    program = load(mod(body, decls), "t.mod")
    trace = program.run({}, arm=arm_of(cell, "abb"), start_joints=cell.robot.home["abb"])
    assert not trace.halted
    assert trace.moves[-1].joints == pytest.approx([10, 20, -10, 30, 60, -40], abs=1e-3)


# --- SearchL ------------------------------------------------------------------------------------------


SEARCH = """MoveL p0, v100, fine, t1;
MoveL p20, v100, fine, t1;
SearchL {switches}diA{flank}, hit, p0, v10, t1;
now := CRobT(\\Tool:=t1 \\WObj:=wobj0);
TPWrite "hit " \\Num:=hit.trans.x;
TPWrite "at " \\Num:=now.trans.x;"""
SEARCH_DATA = "VAR robtarget hit;\nVAR robtarget now;"


def test_search_with_stop_stores_the_hit_and_stops_there():
    """From x = 20 back to 0 at 10 mm/s, \\NegFlank: the gate goes off at x = 10.0 (a cycle exactly there); with
    \\Stop the arm stops at that cycle's pose (the move in the trace ends there) and CRobT finds it there."""
    trace = run(SEARCH.format(switches="\\Stop, ", flank=" \\NegFlank"), SEARCH_DATA)
    assert trace.messages == ["hit 10", "at 10"]
    assert trace.moves[-1].tcp2base[:3, 3] == pytest.approx([10.0, 0, 0])


def test_a_flying_search_goes_on_to_the_end_and_keeps_the_first_hit():
    trace = run(SEARCH.format(switches="", flank=" \\NegFlank"), SEARCH_DATA)
    assert trace.messages == ["hit 10", "at 0"]


def test_search_errors_go_to_the_error_handler_or_stop_the_program():
    """No falling edge back to x = 0 when the gate is beyond 30 mm: ERR_SIGSUPSEARCH (the input is already
    0 when a \\NegFlank search starts); a rising search (the default) that meets nothing: ERR_WHLSEARCH with
    the arm at ToPoint; \\Sup with two edges (\\Flanks: out and back in): ERR_WHLSEARCH. An ERROR handler takes
    them, else the program stops with the error."""
    far = Gate(30.0)
    trace = run(SEARCH.format(switches="", flank=" \\NegFlank"), SEARCH_DATA, gate=far)
    assert trace.halted and trace.halt_message.startswith("ERR_SIGSUPSEARCH")
    routines = (
        TRAP
        + """PROC look()
  VAR robtarget hit;
  VAR robtarget now;
  SearchL \\Stop, diA, hit, p0, v10, t1;
ERROR
  IF ERRNO = ERR_WHLSEARCH THEN
    now := CRobT(\\Tool:=t1 \\WObj:=wobj0);
    TPWrite "none, at " \\Num:=now.trans.x;
    RETURN;
  ENDIF
  RAISE;
ENDPROC
"""
    )
    trace = run("MoveL p0, v100, fine, t1;\nMoveL p20, v100, fine, t1;\nlook;", routines=routines, gate=far)
    assert not trace.halted and trace.messages == ["none, at 0"]
    trace = run(SEARCH.format(switches="\\Stop, ", flank=""), SEARCH_DATA, gate=far)
    assert trace.halted and trace.halt_message.startswith("ERR_WHLSEARCH")
    assert trace.moves[-1].tcp2base[:3, 3] == pytest.approx([0, 0, 0])  # the arm went on to ToPoint


def test_sup_with_more_than_one_hit_is_err_whlsearch():
    class Band(Gate):
        def switch(self, name, t, flange2base):
            return None if name != "diA" else flange2base is not None and 5.0 < flange2base[0, 3] < 8.0

    body = "MoveL p0, v100, fine, t1;\nSearchL \\Sup, diA \\Flanks, hit, p20, v10, t1;"
    trace = run(body, SEARCH_DATA, gate=Band())
    assert trace.halted and trace.halt_message.startswith("ERR_WHLSEARCH") and "2 times" in trace.halt_message
    trace = run(body.replace("\\Sup, ", ""), SEARCH_DATA, gate=Band())
    assert not trace.halted  # a flying search without \Sup keeps the first hit


# --- misuse -------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "decls", "routines", "message"),
    [
        ("CONNECT ino WITH main;", "", TRAP, r"t\.mod:12:1: CONNECT \.\.\. WITH main: a PROC or FUNC, not a TRAP"),
        ("CONNECT ino WITH nowhere;", "", TRAP, r"t\.mod:12:1: .*no TRAP routine here"),
        ("tr;", "", TRAP, r"t\.mod:12:1: tr is a TRAP routine"),
        ("ISignalDI diA, 2;", "", TRAP, r"t\.mod:12:1: ISignalDI takes a signal, a trigger value and an interrupt"),
        ("ISignalDI \\Single \\SingleSafe, diA, 2, ino;", "", TRAP, r"t\.mod:12:1: .*exclude each other"),
        ("ISignalDI diA, 2, ino \\Sleep;", "", TRAP, r"t\.mod:12:23: ISignalDI \\Sleep is not supported"),
        ("SearchL diA, p0, p20, v10;", "", TRAP, r"t\.mod:12:1: SearchL takes Signal, SearchPoint, ToPoint"),
        ("SearchL \\Stop \\SStop, diA, p0, p20, v10, t1;", "", TRAP, r"t\.mod:12:1: .*\\Sup exclude each other"),
        ("SearchL diA \\HighLevel, p0, p20, v10, t1;", "", TRAP, r"t\.mod:12:13: SearchL \\HighLevel is not supported"),
        ("SearchL diA, p0.trans.x + 1, p20, v10, t1;", "", TRAP, r"t\.mod:12:1: .*a robtarget variable"),
        ("IDelete;", "", TRAP, r"t\.mod:12:1: IDelete takes one interrupt variable"),
        ("x := 1;", "VAR num INO;", TRAP, r"t\.mod:10:1: INO declared twice in the module"),
        ("", "", TRAP + "TRAP tr\nENDTRAP\n", r"t\.mod:\d+:1: routine tr defined twice"),
        (
            "",
            "",
            TRAP + "PROC p()\n  VAR intnum mine;\n  CONNECT mine WITH tr;\nENDPROC\n",
            r"t\.mod:\d+:3: CONNECT: mine is routine data",
        ),
    ],
)
def test_misuse_is_refused_when_the_module_is_loaded(body, decls, routines, message):
    with pytest.raises(RunError, match=message):
        load(mod(body, decls, routines), "t.mod")


@pytest.mark.parametrize(
    ("body", "decls", "message"),
    [
        ("ISignalDI diA, 2, ino;", "", r"t\.mod:12:1: ISignalDI: ino is not connected to a TRAP"),
        (
            "CONNECT ino WITH tr;\nISignalDI diA, 2, ino;\nISignalDI diA, 1, ino;",
            "",
            r"t\.mod:14:1: ISignalDI: ino is already ordered",
        ),
        ("CONNECT ino WITH tr;\nCONNECT ino WITH tr;", "", r"t\.mod:13:1: CONNECT: ino is already connected"),
        ("CONNECT ino WITH tr;\nISignalDI diA, 3, ino;", "", r"t\.mod:13:1: ISignalDI: trigger value 3"),
        ("CONNECT ino WITH tr;\nISignalDI diB, 2, ino;", "", r"t\.mod:13:1: .*no device here switches the input diB"),
        ("CONNECT ino WITH tr;\nISignalDI di2, 2, ino;", "VAR num di2;", r"t\.mod:13:1: .*di2 is program data"),
        ("CONNECT n WITH tr;", "", r"t\.mod:12:1: CONNECT: n is a var num, not a VAR intnum"),
        ("CONNECT pin WITH tr;", "PERS intnum pin := 0;", r"CONNECT: pin is a pers intnum, not a VAR intnum"),
        ("x := CRobT(\\Tool:=t1);", "VAR robtarget x;", r"t\.mod:12:6: CRobT takes \\Tool:= and \\WObj:="),
        (
            "MoveL p0, v100, fine, t1;\nMoveC p20, [[40, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], "
            + EXT
            + "], v10, fine, t1;",
            "",
            r"t\.mod:13:1: MoveC: .*on a line",
        ),
        ("MoveL p0, v100, fine, t1;\nMoveC p20, v10, fine, t1;", "", r"t\.mod:13:1: MoveC takes CirPoint, ToPoint"),
        ("MoveL p0, v100, fine, t1;\nMoveC p0, p20, v10, fine, t1;", "", r"MoveC: CirPoint from the start is closer"),
    ],
)
def test_misuse_is_refused_when_it_runs(body, decls, message):
    with pytest.raises(RunError, match=message):
        run(body, decls)


def test_a_trap_may_not_move_the_arm():
    routines = "TRAP tr\n  MoveL p0, v10, fine, t1;\nENDTRAP\n"
    with pytest.raises(RunError, match=r"t\.mod:\d+:3: MoveL in TRAP tr: a TRAP here may not move the arm"):
        run(OUT_AND_BACK.format(trigger=2), routines=routines)
