"""The laser TCP program for ur: it finds the tool, and stops with its messages (against the simulated station)."""

from __future__ import annotations

import numpy as np
import pytest
from support.programs import first, run_case

from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.verify import LaserCase, rotation
from codegen.model.cell import load_cell

CELL = "codegen/examples/laser/laser_tcp.toml"


# --- the laser TCP program ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def laser():
    cell = load_cell(CELL)
    program = first(cell, "ur", "laser").load()
    return cell, program


def _tool(cell, offset=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), degrees=0.0) -> np.ndarray:
    tool = cell.robot.tool.tcp2flange.copy()
    tool[:3, 3] += offset
    tool[:3, :3] = rotation(axis, degrees) @ tool[:3, :3] if degrees else tool[:3, :3]
    return tool


@pytest.mark.parametrize(
    ("offset", "axis", "degrees"),
    [((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 0.0), ((1.2, -0.8, 0.7), (1.0, -2.0, 0.5), 6.0)],
    ids=["straight", "bent"],
)
def test_the_program_finds_the_tcp_within_a_tenth_of_a_millimetre(laser, offset, axis, degrees):
    """The station with the sensors' noise (0.01 mm) and hysteresis (0.05 mm); a straight tool, and one whose tip
    is off its data by (1.2, -0.8, 0.7) mm and whose axis is tilted 6 deg (its end face's rim then meets the beam
    0.14 mm below the tip: the rim's correction matters): the TCP written is the true tool's within 0.1 mm,
    reported, and every edge and hit is kept."""
    cell, program = laser
    tool = _tool(cell, offset, axis, degrees)
    trace = run_case(cell, "ur", program, LaserCase("test", tool, seed=7), "laser")[0]
    assert not trace.halted, trace.halt_message
    names = lp.kept_names(get_target("ur"))
    tcp = np.array([float(v) for v in trace.kept[names["tcp"]]])
    assert np.linalg.norm(tcp - tool[:3, 3]) < 0.1
    assert trace.messages[-1].startswith(lp.WRITTEN)
    assert len(trace.kept[names["edges"]]) == 16 and len(trace.kept[names["hits"]]) == 6


def test_a_tool_too_short_for_the_first_circle_stops_with_its_message(laser):
    cell, program = laser
    tool = _tool(cell, offset=(0.0, 0.0, -7.0))
    trace = run_case(cell, "ur", program, LaserCase("test", tool, seed=7), "laser")[0]
    assert trace.halted
    assert trace.halt_message == Emitter(get_target("ur")).string(lp.CIRCLE_EDGES) + "1"
