"""The laser TCP program for kuka: it finds the tool, and stops with its messages (against the simulated station)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from support.programs import first, load_program

from codegen.controllers import get_target
from codegen.kinds.laser import confirm
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.verify import LaserCase, cases, station_for
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.robot.expect import arm_of
from codegen.sim.operator import Operator

CELL = "codegen/examples/laser/laser_tcp.toml"
CYCLE = 0.012  # targets/kuka.toml signal_cycle_s
TOOL = "TOOL_DATA[3]"  # the cell's production tool
BEFORE = (0.4, -0.3, 180.9, 0.0, 0.0, 0.0)  # its X, Y, Z, A, B, C before the run (the last calibration's)


# --- the program -----------------------------------------------------------------------------------


def _program(cell, drop_wait_before_off: bool = False):
    target = get_target("kuka")
    if not drop_wait_before_off:
        return first(cell, "kuka", "laser").load()
    names = lp.laser_file_names(cell, target)
    files = {f.relpath.rsplit("/", 1)[1]: f for f in render(cell, ["kuka"])}
    lines = files[names[0]].text.split("\n")
    kept = [
        line
        for i, line in enumerate(lines)
        if not ("WAIT SEC 0 " in line and i + 1 < len(lines) and "INTERRUPT OFF" in lines[i + 1])
    ]
    assert len(kept) == len(lines) - 3  # the circles' and the search's two
    return load_program(target, "\n".join(kept), f"<fresh>/{files[names[0]].relpath}", {".dat": files[names[1]].text})


def _run(cell, program, tool: np.ndarray, cycle: float = CYCLE, answers=(confirm.YES,), keep=()):
    target = get_target("kuka")
    station = station_for(cell, target, LaserCase("test", tool, noise=0.0))
    return program.run(
        {TOOL: BEFORE},
        devices=(station, Operator(answers)),
        arm=arm_of(cell, "kuka"),
        start_joints=cell.robot.home["kuka"],
        keep=(*lp.kept_names(target).values(), *keep),
        signal_cycle_s=cycle,
        step_limit=2_000_000,
    )


def _bent(guess: np.ndarray, shift, degrees: float) -> np.ndarray:
    """The tip moved by shift (flange frame), the pin turned by degrees about the flange's y."""
    tool = guess.copy()
    tool[:3, 3] += shift
    a = math.radians(degrees)
    tool[:3, :3] = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]]) @ tool[:3, :3]
    return tool


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.mark.parametrize(
    ("shift", "degrees", "cycle", "within"),
    [
        ((0.0, 0.0, 0.0), 0.0, CYCLE, 0.1),  # straight
        ((1.2, -0.8, 0.7), 0.5, CYCLE, 0.1),  # bent: the tip aside and longer, the axis tilted
        # tilted 3 deg, read every 4 ms (edges 0.04 mm apart on the circles): the end face's rim meets the beam
        # 1.5 sin(3 deg) = 0.08 mm below the tip; corrected, the TCP within 0.02 mm
        ((0.4, 0.3, -0.5), 3.0, 0.004, 0.02),
    ],
)
def test_the_program_finds_the_tcp(cell, shift, degrees, cycle, within):
    tool = _bent(cell.robot.tool.tcp2flange, shift, degrees)
    trace = _run(cell, _program(cell), tool, cycle)
    assert not trace.halted, trace.halt_message
    assert trace.messages[-1].startswith(lp.WRITTEN)
    tcp = np.array(trace.kept["LSR_TCP"], dtype=float)
    assert np.linalg.norm(tcp - tool[:3, 3]) < within
    assert all(v != 0 for v in trace.kept["LSR_EDGE"])  # 16 edges stored
    assert trace.moves[0].kind == "joint" and trace.moves[-1].kind == "joint"  # from home, back home


def test_the_program_without_an_advance_run_stop_before_interrupt_off_loses_the_edges(cell):
    trace = _run(cell, _program(cell, drop_wait_before_off=True), cell.robot.tool.tcp2flange.copy())
    assert trace.halted
    assert trace.halt_message.startswith(lp.CIRCLE_EDGES[:40]) and trace.halt_message.endswith("1")
    assert all(v == 0 for v in trace.kept["LSR_EDGE"])


def test_a_stop_after_a_run_that_wrote_the_tcp_shows_its_circle_number(cell):
    """The data list keeps what a run left (a partial aggregate sets only the components it names): a run after
    one that reported the TCP (three REAL message parameters) stops at the first circle with the circle's number,
    each message parameter holding one value (the interpreter refuses a KrlMsgPar_T with two)."""
    target = get_target("kuka")
    program = _program(cell)
    dat = next(f.text for f in first(cell, "kuka", "laser").files if f.name.lower().endswith(".dat"))
    names = tuple(dict.fromkeys(re.findall(r"^DECL\s+\w+\s+(\w+)", dat, re.M)))
    station = station_for(cell, target, LaserCase("test", cell.robot.tool.tcp2flange, noise=0.0))
    options = {"arm": arm_of(cell, "kuka"), "start_joints": cell.robot.home["kuka"], "signal_cycle_s": CYCLE}
    given, devices = {TOOL: BEFORE}, (station, Operator([confirm.YES]))
    written = program.run(given, devices=devices, keep=names, step_limit=2_000_000, **options)
    assert not written.halted and written.messages[-1].startswith(lp.WRITTEN)
    left = {name: value for name, value in written.kept.items() if value is not None}
    short = cell.robot.tool.tcp2flange.copy()
    short[:3, 3] += short[:3, 2] * -7.0  # the first circle passes under the tip
    station = station_for(cell, target, LaserCase("test", short, noise=0.0))
    stopped = program.run({**left, **given}, devices=(station,), step_limit=2_000_000, **options)
    assert stopped.halted and stopped.halt_message == lp.CIRCLE_EDGES + "1"


# --- the operator's confirmation before the production tool changes ---------------------------------------------


def _edited(cell, old: str, new: str):
    """The program with one piece of its text replaced (a mutation the judge must catch)."""
    target = get_target("kuka")
    names = lp.laser_file_names(cell, target)
    files = {f.relpath.rsplit("/", 1)[1]: f for f in render(cell, ["kuka"])}
    text = files[names[0]].text
    assert old in text
    name, dat = f"<edited>/{files[names[0]].relpath}", files[names[1]].text
    return load_program(target, text.replace(old, new), name, {".dat": dat})


def _shown(trace, prefix: str) -> list[float]:
    return [float(v) for v in next(m for m in trace.messages if m.startswith(prefix))[len(prefix) :].split()]


def test_the_program_shows_the_old_and_new_tcp_and_writes_it_on_yes(cell):
    """Before TOOL_DATA[3] changes: its X, Y, Z now and the TCP found in two notifications, then the dialog; the
    operator's Yes writes the TCP found."""
    tool = _bent(cell.robot.tool.tcp2flange, (1.2, -0.8, 0.7), 0.5)
    trace = _run(cell, _program(cell), tool)
    said = confirm.texts(cell, get_target("kuka"))
    assert _shown(trace, said["tool_now"]) == pytest.approx(BEFORE[:3], abs=1e-4)
    tcp = [float(v) for v in trace.kept["LSR_TCP"]]
    assert _shown(trace, said["tcp_found"]) == pytest.approx(tcp, abs=1e-4)
    asked = trace.messages.index(said["confirm"])
    assert asked < len(trace.messages) - 1 and trace.messages[asked + 1].startswith(lp.WRITTEN)
    written = trace.kept.get(TOOL) if TOOL in trace.kept else None
    assert written is None or [float(written[k]) for k in "XYZ"] == pytest.approx(tcp, abs=1e-4)


def test_the_operator_s_no_leaves_the_production_tool_unchanged_and_says_so(cell):
    target = get_target("kuka")
    program = _program(cell)
    station = station_for(cell, target, LaserCase("test", cell.robot.tool.tcp2flange, noise=0.0))
    options = {"arm": arm_of(cell, "kuka"), "start_joints": cell.robot.home["kuka"], "signal_cycle_s": CYCLE}
    trace = program.run({TOOL: BEFORE}, devices=(station, Operator([confirm.NO])), keep=(TOOL,), **options)
    said = confirm.texts(cell, target)
    assert not trace.halted and trace.messages[-1] == said["not_written"]
    assert not any(m.startswith(lp.WRITTEN) for m in trace.messages)
    assert [float(trace.kept[TOOL][k]) for k in ("X", "Y", "Z", "A", "B", "C")] == pytest.approx(BEFORE)
    assert trace.moves[-1].kind == "joint"  # the way out, home


@pytest.mark.parametrize(
    ("category", "old", "new", "problem"),
    [
        ("confirmation_refused", None, None, None),
        ("as_designed", None, None, None),
        # the tool written whatever the operator answers
        ("confirmation_refused", "  RETURN ANSWER == 1\n", "  RETURN TRUE\n", "TCP not written, tool 3 unchanged"),
        # Yes not taken: the tool never written
        ("as_designed", "  RETURN ANSWER == 1\n", "  RETURN FALSE\n", "expected the TCP written"),
        # the question never asked
        ("as_designed", "IF LSR_CONFIRM() THEN", "IF TRUE THEN", "no message 'laser: tool 3 now"),
    ],
)
def test_verify_judges_the_operator_s_answer(cell, category, old, new, problem):
    """Verify's laser cases on KUKA: the operator answers Yes, and No in "confirmation_refused", whose expectation is
    the production tool unchanged and the message that says so; a program that writes anyway, never writes or never
    asks is a mismatch."""
    from support.programs import run_case

    from codegen.kinds.laser import plan

    source = first(cell, "kuka", "laser")
    every = cases(cell, 0) + confirm.cases(get_target("kuka"), cases(cell, 0)[0])
    case = next(c for c in every if c.category == category)
    program = source.load() if old is None else _edited(cell, old, new)
    trace, _ = run_case(cell, "kuka", program, case, "laser")
    judged = plan.judge(cell, "kuka", case, trace)
    if problem is None:
        assert judged.problem is None and len(judged.accepted) == 1
        stored = {s.name: s for s in judged.accepted[0].stored}
        value = trace.kept[TOOL]
        for field, s in zip("XYZ", (stored[f"{TOOL}.{k}"] for k in "XYZ"), strict=True):
            assert abs(float(value[field]) - s.value) <= s.tolerance, (field, s.what)
        if category == "confirmation_refused":
            assert stored[f"{TOOL}.X"].what == "the production tool unchanged"
    else:
        assert judged.problem is not None and problem in judged.problem, judged.problem


def test_every_target_that_asks_runs_the_refused_case(cell):
    quiet = cases(cell, 0)[0]
    both = ["confirmation_refused", "confirmation_unanswered"]
    for target in ("kuka", "ur", "abb"):
        assert confirm.asks(get_target(target))
        assert [c.category for c in confirm.cases(get_target(target), quiet)] == both
    assert confirm.cases(get_target("dtrans"), quiet) == []


def test_the_confirmation_s_messages_fit_msg_txt_with_the_widest_numbers():
    """Msg_txt is CHAR[80] (targets/kuka.toml string_max): each message with the widest tool number (16) and the
    widest numbers it carries (a TCP within 2,000 mm of the flange); the softkeys' labels within Sk_Txt CHAR[10]."""
    string_max = get_target("kuka").string_max
    numbers = " ".join([lp.NUMBER_MAX] * 3)
    for text, carried in (
        (confirm.TOOL_NOW, numbers),
        (confirm.TCP_FOUND, numbers),
        (confirm.CONFIRM, ""),
        (confirm.NOT_WRITTEN, ""),
    ):
        assert len(text.format(tool="tool 16") + carried) <= string_max, text
    assert all(len(label) <= 10 for label in (confirm.YES, confirm.NO))


# --- each beam's first edge on a circle is the pin coming in ------------------------------------------------


class _LightOn:
    """The station with each sensor set the other way (its output on while the beam is free): every edge is
    where the right sensor's is, inverted."""

    def __init__(self, station) -> None:
        self.station, self.switches = station, station.switches

    def on_wait(self, machine, where: str) -> bool:
        return self.station.on_wait(machine, where)

    def switch(self, name, t, flange2base):
        seen = self.station.switch(name, t, flange2base)
        return None if seen is None else not seen


FIRST_ON = "(NOT LSR_ON[I + 1]) OR (NOT LSR_ON[I + 5])"


@pytest.mark.parametrize("checked", [True, False])
def test_a_beam_whose_first_edge_is_off_stops_at_the_first_circle(cell, checked):
    """m2: LSR_SEEN records each edge's new value; a sensor switching the other way (its first edge on the circle
    is off) stops the program at circle 1 with the circle's message. Without the check (the mutant) the edges
    still count four per beam and the program goes on past the circles."""
    target = get_target("kuka")
    program = _program(cell) if checked else _edited(cell, FIRST_ON, "FALSE OR FALSE")
    station = _LightOn(station_for(cell, target, LaserCase("test", cell.robot.tool.tcp2flange, noise=0.0)))
    options = {"arm": arm_of(cell, "kuka"), "start_joints": cell.robot.home["kuka"], "signal_cycle_s": CYCLE}
    trace = program.run(
        {TOOL: BEFORE}, devices=(station, Operator([confirm.YES])), keep=("LSR_ON",), step_limit=2_000_000, **options
    )
    stopped_at_circle = trace.halted and trace.halt_message == lp.CIRCLE_EDGES + "1"
    assert stopped_at_circle is checked, (trace.halted, trace.halt_message)
    if checked:
        assert list(trace.kept["LSR_ON"][:8]) == [False, True, False, True] * 2


def test_the_edges_of_a_right_sensor_alternate_on_and_off(cell):
    trace = _run(cell, _program(cell), cell.robot.tool.tcp2flange.copy(), keep=("LSR_ON",))
    assert not trace.halted, trace.halt_message
    assert trace.kept["LSR_ON"] == [True, False] * 8
