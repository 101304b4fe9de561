"""The laser TCP program for ur: it finds the tool, and stops with its messages (against the simulated station)."""

from __future__ import annotations

import numpy as np
import pytest
from support.programs import edited, first, regex_edit, run_case, verify_one

from codegen.controllers import get_target
from codegen.dialects.core.values import RunError
from codegen.emit import Emitter
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.verify import LaserCase, previous_tcp, rotation
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


# --- the production tool: the installation variable pin_tcp ---------------------------------------------------


def test_the_program_shows_the_production_tool_before_it_calibrates_and_writes_the_tcp_into_it(laser):
    """The installation holds the last calibration's TCP (as verify gives it): the program's first message shows
    it (mm), the TCP found replaces it in the installation variable (m)."""
    cell, program = laser
    case = LaserCase("test", cell.robot.tool.tcp2flange.copy(), noise=0.0, seed=7)
    trace, setup = run_case(cell, "ur", program, case, "laser")
    previous = previous_tcp(cell, case)
    assert setup.inputs["installation.pin_tcp"] == pytest.approx((*(previous / 1000.0), 0.0, 0.0, 0.0))
    first_message = trace.messages[0]
    assert first_message.startswith(lp.BEFORE)
    shown = [float(v) for v in first_message[len(lp.BEFORE) :].split(",")]
    assert shown == pytest.approx(previous, abs=1e-3)
    written = np.array([float(v) for v in trace.kept["pin_tcp"].values()])
    assert np.linalg.norm(written[:3] * 1000.0 - case.tool[:3, 3]) < 0.01


def test_an_installation_without_the_production_tool_stops_the_program_before_any_move(laser):
    """Without pin_tcp the program's first read of it is the error naming it: no move, no message, nothing written
    (the TCP would else go into a variable of the program's own)."""
    cell, program = laser
    case = LaserCase("test", cell.robot.tool.tcp2flange.copy(), noise=0.0, without_production_tool=True)
    with pytest.raises(RunError) as error:
        run_case(cell, "ur", program, case, "laser")
    assert "undefined variable pin_tcp" in str(error.value)
    assert error.value.trace.moves == [] and error.value.trace.messages == []


def test_verify_runs_the_installation_without_the_production_tool(laser):
    """verify's case of the scenario: the controller's error naming pin_tcp before any move passes; a program that
    does not read it first (the TCP calibrated and written into a variable of its own) is a mismatch."""
    cell, _ = laser
    source = first(cell, "ur", "laser")
    row = verify_one(cell, source, scenarios=frozenset({"production_tool_missing"}))
    assert (row.cases, row.mismatches, row.scenarios) == (1, 0, {"production_tool_missing": 1})
    unread = edited(source, regex_edit(r"^(\s*lsr_before = )pin_tcp\n", r"\1p[0, 0, 0, 0, 0, 0]\n"), "unread")
    row = verify_one(cell, unread, scenarios=frozenset({"production_tool_missing"}))
    assert row.mismatches == 1 and "the installation has no pin_tcp" in row.first_mismatches[0], row.first_mismatches


def test_the_next_node_moves_with_the_production_tool_just_written(laser):
    """The node ends with set_tcp(pin_tcp): a Move node after it that uses the active TCP moves with the calibrated
    tool, not with the tool as designed the calibration moved with."""
    cell, _ = laser
    source = first(cell, "ur", "laser")
    node = "  movel(pose_add(get_actual_tcp_pose(), p[0, 0, 0.01, 0, 0, 0]), a=1.2, v=0.25)\n"  # the production's next
    program = edited(source, lambda text: text.rstrip("\n") + "\n" + node, "next node").load()
    case = LaserCase("test", _tool(cell, offset=(1.2, -0.8, 0.7)), noise=0.0, seed=7)
    trace = run_case(cell, "ur", program, case, "laser")[0]
    assert not trace.halted, trace.halt_message
    written = [float(v) for v in trace.kept["pin_tcp"].values()]
    assert np.linalg.norm(np.array(written[:3]) * 1000.0 - case.tool[:3, 3]) < 0.03
    assert list(trace.moves[-1].settings["tcp"]) == pytest.approx(written, abs=1e-9)
