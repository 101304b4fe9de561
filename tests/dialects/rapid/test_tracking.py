"""RAPID conveyor tracking (ABB's Conveyor Tracking option) as the interpreter models it: a unit moving its work
object with the simulated belt, the queue (sync, start window, minimum distance), WaitWObj, DropWObj, ActUnit."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.interpreter import load
from codegen.sim.belt import Belt, BeltLine, Part, TrackingUnit, UnitSettings

# a belt at 100 mm/s whose encoder gives 10 counts per mm; the unit's frame at x 1000 in the base, its x along
# the base's y (the travel), z up
FRAME = np.array([[0.0, -1.0, 0.0, 1000.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
SETTINGS = UnitSettings("CNV1", 10_000, FRAME, start_mm=200.0, width_mm=300.0, min_gap_mm=50.0, max_mm=800.0)
BELT = Belt(100.0, 10.0)
DECLS = """
TASK PERS wobjdata track := [FALSE, FALSE, "CNV1", [[0, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
CONST robtarget on := [[0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
CONST robtarget up := [[0, 0, 100], [0, 1, 0, 0], [0, 0, 0, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
CONST robtarget still := [[500, 0, 300], [0, 1, 0, 0], [0, 0, 0, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
CONST robtarget unused := [[500, 0, 300], [0, 1, 0, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
PERS tooldata grip := [TRUE, [[0, 0, 100], [1, 0, 0, 0]], [1, [0, 0, 50], [1, 0, 0, 0], 0, 0, 0]];
PERS loaddata part := [2, [0, 0, 20], [1, 0, 0, 0], 0, 0, 0];
VAR num lost := 0;
VAR num status := 0;
VAR num where := 0;
VAR robtarget p;
"""


class NoQueue:
    """The PLC's queue left out: these programs take their parts from the unit's queue alone."""

    def stop(self, machine) -> None:
        return None

    def live(self, belt, name: str, t: float):
        return None


def run(body: str, parts, routines: str = "", settings: UnitSettings = SETTINGS):
    unit = TrackingUnit(settings, BELT, list(parts))
    line = BeltLine(BELT, [], NoQueue(), unit=unit)
    text = f"MODULE T\n{DECLS}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"
    return load(text, "t.mod").run({}, devices=(line,), keep=("lost", "status", "where")), unit


def unit_frame(travel_mm: float) -> np.ndarray:
    out = FRAME.copy()
    out[:3, 3] += FRAME[:3, 0] * travel_mm
    return out


def test_waitwobj_connects_the_part_in_the_start_window_and_moves_follow_it():
    """The part seen at 1 s enters the start window (200 mm past the sync point) at 3 s; the move in the tracked
    work object ends where the object is then, the next one too; an output set at the fine point on the object
    sees the arm carried on with it (the grip while following)."""
    body = (
        "MoveL still, v1000, fine, grip;\nActUnit CNV1;\nWaitWObj track;\n"
        "MoveL up, v100, fine, grip \\WObj:=track;\nMoveL on, v100, fine, grip \\WObj:=track;\n"
        "WaitTime 0.5;\nSetDO do1, 1;\nDropWObj track;\nDeactUnit CNV1;"
    )
    trace, unit = run(body, [Part(1, 1.0, 0.0, 0.0)])
    assert unit.connections == [(1, pytest.approx(3.0, abs=1e-3))]
    first, second = trace.moves[1], trace.moves[2]
    travel = (first.end_time - 1.0) * 100.0  # the object's travel since its sync when the move ends
    want = unit_frame(travel)
    want[:3, 3] += want[:3, 2] * 100.0
    assert first.tcp2base[:3, 3] == pytest.approx(want[:3, 3], abs=0.2)
    assert second.tcp2base[:3, 3] == pytest.approx(unit_frame((second.end_time - 1.0) * 100.0)[:3, 3], abs=0.2)
    out = trace.outputs[0]  # 0.5 s after the last move: 50 mm further along the travel
    assert out.time == pytest.approx(second.end_time + 0.5)
    assert out.tcp2base[:3, 3] - second.tcp2base[:3, 3] == pytest.approx([0.0, 50.0, 0.0], abs=0.2)


def test_a_move_in_another_work_object_leaves_the_object_and_dropwobj_resets_the_position():
    """After DropWObj the work object is where the unit's position 0 puts it (the sync point); the arm stays where
    the object carried it."""
    body = (
        "ActUnit CNV1;\nMoveL still, v1000, fine, grip;\nWaitWObj track;\nMoveL on, v100, fine, grip \\WObj:=track;\n"
        "DropWObj track;\nWaitTime 1;\nSetDO do1, 1;\nMoveL on, v100, fine, grip \\WObj:=track;"
    )
    trace, unit = run(body, [Part(1, 1.0, 0.0, 0.0)])
    held = trace.moves[1].tcp2base
    assert trace.outputs[0].tcp2base[:3, 3] == pytest.approx(held[:3, 3], abs=1e-6)  # not carried on after the drop
    assert trace.moves[2].tcp2base[:3, 3] == pytest.approx(FRAME[:3, 3], abs=1e-6)  # the sync point
    assert unit.drops == [(1, pytest.approx(trace.moves[1].end_time))]


def test_the_queue_takes_the_oldest_part_skips_one_out_of_the_window_and_ignores_one_too_close():
    """Part 1 has left the start window (500 mm past its sync) when WaitWObj is called at about 6 s: it is gone
    from the queue; part 3 comes 30 mm (0.3 s) after part 2, closer than the minimum distance: its sync is
    ignored; WaitWObj connects part 2 (once 200 mm past its sync), then, after a drop, part 4."""
    parts = [Part(1, 0.5, 0, 0), Part(2, 6.0, 0, 0), Part(3, 6.3, 0, 0), Part(4, 9.0, 0, 0)]
    body = (
        "ActUnit CNV1;\nMoveL still, v1000, fine, grip;\nWaitTime 6;\nWaitWObj track;\nDropWObj track;\n"
        "WaitWObj track;\nDropWObj track;"
    )
    _trace, unit = run(body, parts)
    assert unit.ignored() == {3}
    assert [seq for seq, _t in unit.connections] == [2, 4]
    assert unit.connections[0][1] == pytest.approx(8.0, abs=1e-3)  # 200 mm past its sync


def test_an_object_lost_from_the_start_window_while_waitwobj_waits_goes_to_the_error_handler():
    """WaitWObj \\RelDist beyond the start window: the object leaves the window (500 mm past its sync, at 6 s)
    before it gets there: WaitWObj's error handler runs then (ERR_CNV_DROPPED), the program goes on."""
    routines = (
        "PROC take()\n  WaitWObj track \\RelDist:=600;\nERROR\n  lost := 1;\n  IF ERRNO = ERR_CNV_DROPPED THEN\n"
        "    lost := 2;\n  ENDIF\n  RETURN;\nENDPROC"
    )
    body = "ActUnit CNV1;\ntake;\nSetDO do1, 1;"
    trace, unit = run(body, [Part(1, 1.0, 0, 0)], routines)
    assert trace.kept["lost"] == 2 and unit.lost_waiting == [(1, pytest.approx(6.0, abs=1e-3))]
    assert trace.outputs[0].time == pytest.approx(6.0, abs=1e-3) and not unit.connections


def test_the_units_rules_are_the_controllers_errors():
    """A unit not in the configuration: refused by name; a move in its work object before ActUnit: ERR_CNV_NOT_ACT;
    WaitWObj on a connected work object: ERR_CNV_CONNECT; a WaitWObj no part will end: an error, not a hang."""
    with pytest.raises(RunError, match="CNV2 is not in this controller's configuration"):
        run("ActUnit CNV2;", [])
    trace, _unit = run("MoveL on, v100, fine, grip \\WObj:=track;", [])
    assert trace.halted and trace.halt_message.startswith("ERR_CNV_NOT_ACT") and not trace.moves
    trace, _unit = run("ActUnit CNV1;\nWaitWObj track;\nWaitWObj track;", [Part(1, 0.0, 0, 0), Part(2, 1.0, 0, 0)])
    assert trace.halted and trace.halt_message.startswith("ERR_CNV_CONNECT")
    with pytest.raises(RunError, match="never comes"):
        run("ActUnit CNV1;\nWaitWObj track;", [])


def test_gripload_puts_the_payload_into_the_load_at_the_flange():
    """GripLoad part (2 kg, 20 mm along the tool's z from the TCP, 100 mm from the flange): with the tool's 1 kg at
    50 mm the load at the flange is 3 kg at (50 + 2 * 120) / 3 mm; GripLoad load0 takes it off again."""
    body = (
        "MoveL still, v1000, fine, grip;\nGripLoad part;\nMoveL up, v1000, fine, grip;\nGripLoad load0;\n"
        "MoveL still, v1000, fine, grip;"
    )
    trace, _unit = run(body, [])
    loads = [move.settings["load"] for move in trace.moves]
    assert loads[0][:4] == pytest.approx((1.0, 0.0, 0.0, 50.0))
    assert loads[1][:4] == pytest.approx((3.0, 0.0, 0.0, (50.0 + 2 * 120.0) / 3.0))
    assert loads[2][:4] == pytest.approx((1.0, 0.0, 0.0, 50.0))


def test_an_active_units_axis_must_hold_a_value_in_every_target():
    """While CNV1 (logical axis 7) is active, a MoveL, a MoveJ or a MoveAbsJ whose eax_a is 9E+09 is refused; before
    ActUnit and after DeactUnit it is not; another slot's 9E+09 is no matter."""
    trace, _unit = run("MoveL unused, v1000, fine, grip;\nActUnit CNV1;\nMoveL still, v1000, fine, grip;", [])
    assert len(trace.moves) == 2
    for move in ("MoveL unused, v1000, fine, grip;", "MoveJ unused, v1000, fine, grip;"):
        with pytest.raises(RunError, match=r"eax_a is 9E\+09 .* logical axis 7 of the active unit CNV1"):
            run(f"ActUnit CNV1;\n{move}", [])
    with pytest.raises(RunError, match=r"joint target: eax_a is 9E\+09"):
        run("ActUnit CNV1;\nMoveAbsJ [[0, 0, 0, 0, 90, 0], [9E9, 0, 0, 0, 0, 0]] \\NoEOffs, v1000, fine, grip;", [])
    trace, _unit = run("ActUnit CNV1;\nDeactUnit CNV1;\nMoveL unused, v1000, fine, grip;", [])
    assert len(trace.moves) == 1


def test_the_current_position_reads_the_connected_objects_travel_in_the_units_axis():
    """Connected at 3 s to the part seen at 1 s (200 mm past its sync), 1 s later the unit's joint reads 300 mm
    (CRobT here: the test has no arm's joints for CJointT, which fills the slot the same way); 0 with none connected
    after DropWObj."""
    body = (
        "MoveL still, v1000, fine, grip;\nActUnit CNV1;\nWaitWObj track;\n"
        "WaitTime 1;\np := CRobT(\\Tool:=grip);\nstatus := p.extax.eax_a;\nDropWObj track;\np := CRobT(\\Tool:=grip);\n"
        "where := p.extax.eax_a + 1;"
    )
    trace, _unit = run(body, [Part(1, 1.0, 0, 0)])
    assert trace.kept["status"] == pytest.approx(300.0, abs=0.2) and trace.kept["where"] == pytest.approx(1.0)


def test_waitwobj_maxtime_raises_err_wait_maxtime_and_leaves_the_object_to_come():
    """WaitWObj \\MaxTime:=1 at 0 s for an object in the start window at 3 s: ERR_WAIT_MAXTIME at 1 s (the handler
    runs); the next WaitWObj without it connects the same object at 3 s."""
    routines = (
        "PROC take()\n  WaitWObj track \\MaxTime:=1;\n  status := 1;\nERROR\n  IF ERRNO = ERR_WAIT_MAXTIME THEN\n"
        "    status := 2;\n  ENDIF\n  RETURN;\nENDPROC"
    )
    trace, unit = run("ActUnit CNV1;\ntake;\nSetDO do1, 1;\nWaitWObj track;", [Part(1, 1.0, 0, 0)], routines)
    assert trace.kept["status"] == 2 and trace.outputs[0].time == pytest.approx(1.0, abs=1e-3)
    assert unit.connections == [(1, pytest.approx(3.0, abs=1e-3))]
