"""The laser TCP program for kuka: it finds the tool, and stops with its messages (against the simulated station)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from support.programs import first, load_program

from codegen.controllers import get_target
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.verify import LaserCase, station_for
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.robot.expect import arm_of

CELL = "codegen/examples/laser/laser_tcp.toml"
CYCLE = 0.012  # targets/kuka.toml signal_cycle_s


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


def _run(cell, program, tool: np.ndarray, cycle: float = CYCLE):
    target = get_target("kuka")
    station = station_for(cell, target, LaserCase("test", tool, noise=0.0))
    return program.run(
        {},
        devices=(station,),
        arm=arm_of(cell, "kuka"),
        start_joints=cell.robot.home["kuka"],
        keep=tuple(lp.kept_names(target).values()),
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
    written = program.run({}, devices=(station,), keep=names, step_limit=2_000_000, **options)
    assert not written.halted and written.messages[-1].startswith(lp.WRITTEN)
    left = {name: value for name, value in written.kept.items() if value is not None}
    short = cell.robot.tool.tcp2flange.copy()
    short[:3, 3] += short[:3, 2] * -7.0  # the first circle passes under the tip
    station = station_for(cell, target, LaserCase("test", short, noise=0.0))
    stopped = program.run(left, devices=(station,), step_limit=2_000_000, **options)
    assert stopped.halted and stopped.halt_message == lp.CIRCLE_EDGES + "1"
