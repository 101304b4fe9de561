"""The laser TCP programs as a commissioning engineer loads them: the TCP found goes into the production tool, its
range is the tool as designed's, the way in and out passes a safe pose, a stop in the station backs out."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from support.programs import first, run_case

from codegen.cli import main
from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.verify import LaserCase, cases, previous_tcp
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.verify.checks import move_settings

CELL = "codegen/examples/laser/laser_tcp.toml"
TARGETS = ["ur", "kuka", "abb"]


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.fixture(scope="module", params=TARGETS)
def loaded(request, cell):
    return request.param, first(cell, request.param, "laser").load()


def _case(cell, category: str) -> LaserCase:
    return next(c for c in cases(cell, 0) if c.category == category)


def _production_tcp(cell, target_name: str, trace) -> np.ndarray | None:
    """X, Y, Z of the production tool when the run ended (mm), read where the controller keeps it."""
    target = get_target(target_name)
    value = trace.kept.get(lp.production_name(cell, target))
    if value is None:
        return None
    for field in ("tframe", "trans") if target_name == "abb" else ():  # a RAPID tooldata's position
        value = next(v for k, v in value.items() if str(k).lower() == field)
    scale = 1000.0 if target_name == "ur" else 1.0  # UR's pose in m
    return np.array([float(value[k]) for k in value if str(k).upper() in ("X", "Y", "Z")]) * scale


def _in_s(cell, pose: np.ndarray) -> np.ndarray:
    return (np.linalg.inv(cell.sections["laser"].sensor_frame.matrix()) @ pose)[:3, 3]


def test_the_tcp_found_goes_into_the_production_tool(cell, loaded):
    """A bent tool: the TCP found is in the production tool the cell names (KRL TOOL_DATA[3] of $config.dat, the
    production task's PERS tooldata tPin, the installation variable pin_tcp), not in data of the program's own."""
    target_name, program = loaded
    case = next(c for c in cases(cell, 0) if c.category == "bent")
    trace, _setup = run_case(cell, target_name, program, case, "laser")
    assert not trace.halted, trace.halt_message
    found = np.array([float(v) for v in trace.kept[lp.kept_names(get_target(target_name))["tcp"]]])
    stored = _production_tcp(cell, target_name, trace)
    assert stored is not None, f"{target_name}: the production tool was not written"
    assert np.abs(stored - found).max() < 1e-3
    assert np.linalg.norm(stored - case.tool[:3, 3]) < 0.1


def test_the_range_is_the_tool_as_designed_not_the_last_result(cell, loaded):
    """The tool has bent 1.2 mm since it was designed at the last calibration and 2.4 mm more since: 3.6 mm from
    the tool as designed, beyond offset_max_mm (3 mm), though within it of the last result: stopped, not
    written, the production tool as the last calibration left it."""
    target_name, program = loaded
    case = _case(cell, "drifted_since_last")
    trace, _setup = run_case(cell, target_name, program, case, "laser")
    assert trace.halted and trace.halt_message == Emitter(get_target(target_name)).string(lp.TOO_FAR)
    stored = _production_tcp(cell, target_name, trace)
    last = previous_tcp(cell, case)
    assert stored is not None and np.abs(stored - last).max() < 1e-3  # UR: the installation variable as it was


def test_the_way_in_and_out_passes_the_safe_pose_and_travel_blends(cell, loaded):
    """From home a joint move to the safe pose (100 mm straight above the circles' start), then down above the
    start, blended (the cell's zone_mm 5 mm; KRL stops at the end of a PTP); at the circle's start the arm stops
    exactly (the interrupts go on there); out through the safe pose, home last."""
    target_name, program = loaded
    trace, _setup = run_case(cell, target_name, program, _case(cell, "as_designed"), "laser")
    laser = cell.sections["laser"]
    safe, above = np.array(lp.safe_point(laser)), np.array(lp.circle_points(laser, 0)["above"])
    start = np.array(lp.circle_points(laser, 0)["start"])
    moves = trace.moves
    assert moves[0].kind == "joint" and moves[1].kind == "joint"
    assert np.linalg.norm(_in_s(cell, moves[1].tcp2base) - safe) < 0.01
    assert np.linalg.norm(_in_s(cell, moves[2].tcp2base) - above) < 0.01
    assert np.linalg.norm(_in_s(cell, moves[3].tcp2base) - start) < 0.01
    assert np.linalg.norm(_in_s(cell, moves[-2].tcp2base) - safe) < 0.01 and moves[-1].kind == "joint"
    joint_zone = cell.motion.zone_mm if get_target(target_name).kind_tables["laser"]["joint_zone"] else 0.0
    work = cell.motion.work_speed_mm_s

    def settings(kind, zone, speed):
        return move_settings(target_name, kind, zone == 0.0, True, speed, zone, cell.motion.joint_speed_percent)

    for i, (kind, zone, speed) in {
        1: ("joint", joint_zone, cell.motion.speed_mm_s),
        2: ("linear", cell.motion.zone_mm, work),
        3: ("linear", 0.0, work),
        len(moves) - 2: ("linear", joint_zone, work),
    }.items():
        for key, want in settings(kind, zone, speed).items():
            assert moves[i].settings.get(key) == pytest.approx(want), (target_name, i, key)


def test_a_restart_in_the_station_backs_out_along_the_tool_s_axis(cell, loaded):
    """Started where a stopped calibration left the arm (the pin at the first circle's start, 5 mm below the beams):
    a motion where it stands, straight up (S's x and y kept) to the safe height, the safe pose, home, and then the
    whole calibration, which writes the production tool."""
    target_name, program = loaded
    case = _case(cell, "start_mid_cycle")
    trace, _setup = run_case(cell, target_name, program, case, "laser")
    assert not trace.halted, trace.halt_message
    laser = cell.sections["laser"]
    begin, safe = np.array(lp.circle_points(laser, 0)["start"]), np.array(lp.safe_point(laser))
    moves = trace.moves
    assert moves[0].kind == "joint" and np.linalg.norm(_in_s(cell, moves[0].tcp2base) - begin) < 0.01
    up = _in_s(cell, moves[1].tcp2base)
    assert moves[1].kind == "linear" and np.abs(up - (begin[0], begin[1], safe[2])).max() < 0.01
    assert moves[2].kind == "linear" and np.linalg.norm(_in_s(cell, moves[2].tcp2base) - safe) < 0.01
    assert moves[3].kind == "joint"  # home
    assert _production_tcp(cell, target_name, trace) is not None


def test_a_start_elsewhere_stops_before_the_arm_moves(cell, loaded):
    """Started away from home and from the station (25, -15, 10 deg off home): the operator's message, and no move
    (KRL: its BCO run where the arm stands, before it reads where the TCP is, goes nowhere)."""
    target_name, program = loaded
    trace, setup = run_case(cell, target_name, program, _case(cell, "start_away"), "laser")
    assert trace.halted and trace.halt_message == Emitter(get_target(target_name)).string(lp.START_AWAY)
    assert len(trace.moves) <= 1
    if trace.moves:
        assert trace.moves[0].kind == "joint"
        assert np.abs(np.array(trace.moves[0].joints) - setup.start_joints).max() < 1e-6


@pytest.mark.parametrize("target_name", TARGETS)
def test_every_operator_message_fits_the_controller(cell, target_name):
    """Every message the laser program shows, with the widest numbers it carries (a TCP within 2,000 mm of the
    flange, 3 decimals), within the controller's string (KRL Msg_txt CHAR[80], a RAPID string 80 characters), and
    whole in the program: none is cut."""
    target = get_target(target_name)
    widest = lp.NUMBER_MAX
    messages = {
        lp.CIRCLE_EDGES + "2",
        lp.NO_TIP,
        lp.AXIS_TILT,
        lp.TOO_FAR,
        lp.START_AWAY,
        lp.SPREAD,
        f"{lp.WRITTEN}{widest}, {widest}, {widest}",
    }
    for message in messages:
        assert len(message) <= target.string_max, (target_name, message)
    text = "\n".join(f.text for f in render(cell, [target_name]) if "/tcp_" in f.relpath)
    for message in (
        lp.CIRCLE_EDGES.rstrip(),
        lp.NO_TIP,
        lp.AXIS_TILT,
        lp.TOO_FAR,
        lp.START_AWAY,
        lp.SPREAD,
        lp.WRITTEN.rstrip(),
    ):
        assert message in text, (target_name, message)
    assert not re.search(r'\.\.\."', text)  # no message cut short with "..."


def test_a_restart_from_any_pose_the_calibration_takes_is_in_the_station_s_column(cell):
    """The column a stopped calibration backs out of holds every pose of the calibration (the reach proof's, both
    circles and the search's line wherever offset_max_mm puts it, the safe pose) with room to spare."""
    from codegen.kinds.laser.reach import path

    laser = cell.sections["laser"]
    column = lp.zone(laser)
    for what, pose in path(cell):
        x, y, z = _in_s(cell, pose)
        assert np.hypot(x, y) < column["r"] - 1.0 and column["low"] + 1.0 < z < column["high"] - 1.0, what


@pytest.mark.parametrize(
    ("target_name", "name", "refusal"),
    [
        ("abb", "here", "the program's own name here"),  # a variable of the program's main routine
        ("abb", "tool0", "a word or predefined name"),  # RAPID's predefined tool: no program may write it
        ("ur", "norm", "a word or predefined name"),  # a URScript built-in
        ("ur", "lsr_found", "laser.production_tool.ur"),  # refused by the section: the program's own prefix
    ],
)
def test_a_production_tool_named_like_the_program_s_own_or_the_language_s_names_is_refused(
    tmp_path, target_name, name, refusal
):
    """The production tool's name is the cell's, written as it is: one the program uses itself, or one the language
    reserves or predefines, is refused with the key named (exit 2), nothing written."""
    text = Path(CELL).read_text(encoding="utf-8")
    old = {"abb": 'abb = "tPin"', "ur": 'ur = "pin_tcp"'}[target_name]
    path = tmp_path / "laser_tcp.toml"
    path.write_text(text.replace(old, f'{target_name} = "{name}"'))
    result = CliRunner().invoke(main, ["generate", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert f"laser.production_tool.{target_name}" in result.output and refusal in result.output, result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()
