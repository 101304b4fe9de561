"""The laser TCP program for abb: it finds the tool, and stops with its messages (against the simulated station)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from support.programs import first

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.dialects.rapid.interpreter import load
from codegen.kinds.laser import confirm
from codegen.kinds.laser import program as lp
from codegen.model.cell import load_cell
from codegen.model.io import signal_name
from codegen.robot.expect import arm_of
from codegen.sim.beam_station import BeamStation
from codegen.sim.beams import Pin
from codegen.sim.operator import Operator

CELL = "codegen/examples/laser/laser_tcp.toml"


# --- the program -------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def laser_program():
    """The program module with the system module that declares the production tool (one task)."""
    cell = load_cell(CELL)
    return cell, get_target("abb"), first(cell, "abb", "laser").load()


def bent(tool: np.ndarray, shift, degrees: float, about) -> np.ndarray:
    out = tool.copy()
    out[:3, 3] += shift
    axis = np.asarray(about, dtype=float) / np.linalg.norm(about)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    a = math.radians(degrees)
    out[:3, :3] = (np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * k @ k) @ out[:3, :3]
    return out


def run_program(laser_program, tool: np.ndarray, noise: float = 0.0, hysteresis: float = 0.0, seed: int = 0, keep=()):
    cell, target, program = laser_program
    laser = cell.sections["laser"]
    inputs = {
        signal_name(target, "input", laser.beam_x["abb"]): "x",
        signal_name(target, "input", laser.beam_y["abb"]): "y",
    }
    station = BeamStation(
        laser.sensor_frame.matrix(),
        Pin(tool, laser.pin_radius_mm),
        inputs,
        noise=noise,
        hysteresis=hysteresis,
        seed=seed,
    )
    return program.run(
        {},
        devices=(station, Operator([confirm.YES])),  # the operator confirms the TCP found
        arm=arm_of(cell, "abb"),
        start_joints=cell.robot.home["abb"],
        keep=(*lp.kept_names(target).values(), *keep),
        signal_cycle_s=target.program["signal_cycle_s"],
        step_limit=2_000_000,
    )


@pytest.mark.parametrize(
    ("shift", "degrees", "about", "noise"),
    [
        ((0, 0, 0), 0.0, (0, 0, 1), 0.0),
        ((1.2, -0.8, 0.7), 0.5, (0, 1, 0), 0.0),
        ((-0.9, 1.1, -1.3), 1.8, (1, 2, 0.5), 0.01),
        ((0.5, 0.3, -0.4), 3.0, (0, 1, 0), 0.0),
    ],
)
def test_the_program_finds_a_straight_and_a_bent_tool_within_a_tenth(laser_program, shift, degrees, about, noise):
    """The tool as designed, bent 0.5 deg with its tip 1.2, -0.8, 0.7 mm off, bent 1.8 deg with the sensors'
    noise and hysteresis, bent 3 deg about y (its end face's rim 0.08 mm below the tip): the TCP found (kept and
    written into the tool's data) within 0.1 mm; without noise within 0.03 mm (an edge seen up to a cycle late,
    0.04 mm at the circle speed, mostly cancels in the means of edges in and out)."""
    cell = laser_program[0]
    tool = bent(cell.robot.tool.tcp2flange, shift, degrees, about)
    trace = run_program(laser_program, tool, noise=noise, hysteresis=0.05 if noise else 0.0, seed=7)
    assert not trace.halted, trace.halt_message
    tcp = np.array([float(v) for v in trace.kept["lsr_tcp"]])
    assert np.linalg.norm(tcp - tool[:3, 3]) < (0.1 if noise else 0.03)
    assert trace.messages[-1].startswith(lp.WRITTEN)
    written = [float(v) for v in trace.messages[-1][len(lp.WRITTEN) :].split(",")]
    assert written == pytest.approx(list(tcp), abs=1e-3)
    edges = [float(v) for v in trace.kept["lsr_edge"]]
    assert all(abs(v) < 5.0 for v in edges) and sum(v != 0 for v in edges) == 16


@pytest.mark.parametrize(
    ("dz", "message"),
    [(-7.0, lp.CIRCLE_EDGES + "1"), (4.5, lp.TOO_FAR), (9.0, lp.NO_TIP)],
)
def test_the_program_stops_with_the_operator_s_message(laser_program, dz, message):
    """A tool 7 mm shorter than its data: the first circle passes under the tip; 4.5 mm longer: found, farther
    than offset_max, not written; 9 mm longer: the tip is in beam X where the search starts (ERR_SIGSUPSEARCH,
    taken by the routine's ERROR handler)."""
    cell = laser_program[0]
    tool = cell.robot.tool.tcp2flange.copy()
    tool[:3, 3] += tool[:3, 2] * dz
    trace = run_program(laser_program, tool)
    assert trace.halted and trace.halt_message == message
    beams_z = cell.sections["laser"].sensor_frame.matrix()[2, 3]
    assert trace.moves[-1].tcp2base[2, 3] > beams_z  # stopped above the beams
    assert [trace.motion_settings[k]["on"] for k in ("confj", "confl")] == [True, True]  # checks on before the stop


def test_a_name_for_both_data_and_a_routine_is_refused():
    """RAPID names ignore case and name one object in a scope: CONST COUNT and FUNC count clash (the pallet
    template had STACK_COUNT and stack_count until this check found it)."""

    text = (
        "MODULE m\n  LOCAL CONST num COUNT := 1;\n  LOCAL FUNC num count(num n)\n    RETURN n;\n  ENDFUNC\n"
        '  PROC main()\n    TPWrite "x";\n  ENDPROC\nENDMODULE\n'
    )
    with pytest.raises(RunError, match="names both data and a routine"):
        load(text, "clash.mod")


def test_the_module_loads_into_a_production_task_whose_main_calls_its_entry(laser_program):
    """The production task has its own PROC main: the laser module declares none (two global routines of one name
    clash in a task) and its entry routine, called from that main, calibrates and writes the production tool."""
    cell, target, _ = laser_program
    files = list(first(cell, "abb", "laser").files)
    assert not any(re.search(r"^\s*PROC\s+main\s*\(", f.text, re.I | re.M) for f in files)
    entry = first(cell, "abb", "laser").entry
    production = SourceFile(
        "production.mod",
        f"MODULE production\n  PROC main()\n    {entry};\n    MoveAbsJ [[0, 0, 0, 0, 90, 0], "
        "[9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]]\\NoEOffs, v200, fine, tool0;\n  ENDPROC\nENDMODULE\n",
    )
    (task,) = Rapid.programs([*files, production])
    name = lp.production_name(cell, target)
    trace = run_program((cell, target, Rapid.load_files(task)), cell.robot.tool.tcp2flange, keep=(name,))
    assert not trace.halted and trace.messages[-1].startswith(lp.WRITTEN)
    trans = trace.kept[name]["TFRAME"]["TRANS"]
    assert [float(trans[k]) for k in "XYZ"] == pytest.approx([float(v) for v in trace.kept["lsr_tcp"]])


def test_the_production_main_goes_on_with_the_configuration_checks_on(laser_program):
    """The routine switches ConfJ and ConfL off for its computed poses; a routine call keeps what it leaves (RAPID
    resets them only at a program load or a start from main): the production main's next move runs with both on."""
    cell, target, _ = laser_program
    plan = first(cell, "abb", "laser")
    production = SourceFile(
        "production.mod",
        f"MODULE production\n  PROC main()\n    {plan.entry};\n    MoveJ Offs(CRobT(), 0, 0, 10), "
        "v200, fine, tool0;\n  ENDPROC\nENDMODULE\n",
    )
    (task,) = Rapid.programs([*plan.files, production])
    trace = run_program((cell, target, Rapid.load_files(task)), cell.robot.tool.tcp2flange)
    assert not trace.halted
    settings = trace.moves[-1].settings
    assert settings["speed"] == "V200" and settings["confj"]["on"] and settings["confl"]["on"]


# --- the runs' spread in the event log ---------------------------------------------------------------------


def _logged_spread(trace) -> float | None:
    said = [m for m in trace.messages if m.startswith(lp.SPREAD_SEEN)]
    return float(said[-1][len(lp.SPREAD_SEEN) :]) if said else None


@pytest.mark.parametrize("category", ["bent", "tool_growing"])
def test_every_calibration_logs_its_runs_spread(laser_program, category):
    """m6: the farthest run's distance from the runs' mean goes to the event log (ErrWrite \\I) on every calibration,
    before the spread check: where the runs agree (a bent tool with the sensors' noise: written) and where they do
    not (a tool that grows while it is calibrated: stopped for the spread). The value logged is the spread of the
    runs' TCPs the program kept, computed here in float64."""
    from support.programs import run_case

    from codegen.kinds.laser import verify as lv

    cell, target, program = laser_program
    case = next(c for c in lv.cases(cell, 0) if c.category == category)
    trace, _ = run_case(cell, "abb", program, case, "laser")
    runs = lv.runs_of(cell, lv.kept_values(target, trace))
    assert len(runs) == cell.sections["laser"].runs
    logged = _logged_spread(trace)
    assert logged is not None, trace.messages
    assert logged == pytest.approx(lv.spread(runs), abs=1e-3)
    stopped = trace.halted and trace.halt_message == lp.SPREAD
    assert stopped is (category == "tool_growing"), trace.halt_message
    logged_at = next(i for i, m in enumerate(trace.messages) if m.startswith(lp.SPREAD_SEEN))
    assert logged_at < len(trace.messages) - 1  # before the stop's message or the confirmation
