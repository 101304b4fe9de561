"""Inputs that switch while the arm moves (core/watch.py), the laser station device and the exact-edge reference."""

from __future__ import annotations

import math
from pathlib import Path as FilePath

import numpy as np
import pytest

from codegen.controllers import get_target
from codegen.dialects.core.machine import Machine, MoveEvent
from codegen.dialects.core.watch import Path
from codegen.kinds.laser.reference import expected
from codegen.kinds.laser.verify import cases, rotation, station_for
from codegen.model.cell import load_cell
from codegen.sim.beam_station import BeamStation
from codegen.sim.beams import Pin

CELL = "codegen/examples/laser/laser_tcp.toml"


def _at(x: float, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def test_a_circular_path_runs_through_its_three_points_at_the_arc_length():
    """Start (10, 0), via (0, 10), end (-10, 0): a half circle of radius 10 about the origin, 31.4 mm long;
    at a quarter of it the TCP is at 45 deg; the orientation stays the start's."""
    start, via, end = _at(10, 0, 5), _at(0, 10, 5), _at(-10, 0, 5)
    start[:3, :3] = rotation((0, 0, 1), 30)
    path = Path(start, end, via)
    assert path.length == pytest.approx(10 * math.pi)
    h = 10 / math.sqrt(2)
    assert path.pose(0.25)[:3, 3] == pytest.approx([h, h, 5])
    assert path.pose(1.0)[:3, 3] == pytest.approx([-10, 0, 5])
    assert np.allclose(path.pose(0.5)[:3, :3], start[:3, :3])
    assert Path(_at(0), _at(3, 4)).pose(0.5)[:3, 3] == pytest.approx([1.5, 2, 0])


class _Gate:
    """A light gate at x = 5.03 mm (base frame): on while the flange is past it."""

    switches = frozenset({"gate"})

    def on_wait(self, machine, where):
        return False

    def switch(self, name, t, flange2base):
        return None if flange2base is None else bool(flange2base[0, 3] >= 5.03)


def test_an_edge_reaches_its_handler_at_the_first_cycle_after_it_with_the_pose_there():
    """A move from x = 0 to 10 mm at 10 mm/s starting at 1 s, cycle 12 ms: the gate switches at 1.503 s; the
    controller sees it at the cycle 1.512 s (126 x 12 ms), where the TCP is at 5.12 mm; switched off, the
    next pass is not seen."""
    machine = Machine(None, {}, 1000, (_Gate(),), None, signal_cycle_s=0.012)
    machine.arm.tcp2flange = np.eye(4)
    machine.move(MoveEvent("linear", _at(0.0), 1), 10.0)
    seen = []
    watcher = machine.watching.watch("gate", "rising", lambda t, pose: seen.append((t, pose[0, 3])))
    machine.move(MoveEvent("linear", _at(10.0), 2), 10.0)
    assert len(seen) == 1
    assert seen[0][0] == pytest.approx(1.512)  # the first move, from an unknown pose, took 1 s
    assert seen[0][1] == pytest.approx(5.12)
    assert machine.input_signal("gate") is True
    machine.watching.unwatch(watcher)
    machine.move(MoveEvent("linear", _at(0.0), 3), 10.0)
    machine.move(MoveEvent("linear", _at(10.0), 4), 10.0)
    assert len(seen) == 1


def test_a_move_that_runs_ahead_delivers_its_edges_only_when_the_clock_gets_there():
    """An advance run: the move is commanded, the program's clock stays; the edge reaches its handler when
    the program waits for the arm (arrive), and not at all when the watcher is switched off before."""
    for switch_off_first, count in ((False, 1), (True, 0)):
        machine = Machine(None, {}, 1000, (_Gate(),), None, signal_cycle_s=0.004)
        machine.arm.tcp2flange = np.eye(4)
        machine.move(MoveEvent("linear", _at(0.0), 1), 10.0)
        seen = []
        watcher = machine.watching.watch("gate", "both", lambda t, pose, seen=seen: seen.append(t))
        machine.move(MoveEvent("linear", _at(10.0), 2), 10.0, runs_ahead=True)
        assert seen == []
        if switch_off_first:
            machine.watching.unwatch(watcher)
        machine.arrive("x:1:1")
        assert len(seen) == count


def test_the_station_sees_the_pin_where_the_geometry_puts_it():
    """A straight pin of radius 1.5 pointing down, its axis at x = 1.4 (S): beam Y (the line x = 0) meets
    it, beam X (y = 0) does too; at x = 1.6 beam Y does not; lifted so its tip is 0.02 mm above the plane,
    neither does beam X, and grown by 0.05 it does."""
    tool = np.eye(4)
    tool[2, 3] = 100.0
    station = BeamStation(np.eye(4), Pin(tool, 1.5), {"x": "x", "y": "y"})

    def flange(x, tip_z):
        out = np.diag([1.0, -1.0, -1.0, 1.0])
        out[:3, 3] = (x, 0.0, tip_z + 100.0)
        return out

    assert station.meets("y", flange(1.4, -5.0), 0.0) and station.meets("x", flange(1.4, -5.0), 0.0)
    assert not station.meets("y", flange(1.6, -5.0), 0.0)
    assert not station.meets("x", flange(0.0, 0.02), 0.0)
    assert station.meets("x", flange(0.0, 0.02), 0.05)


def test_the_reference_finds_straight_and_bent_tools_and_stops_where_the_program_must():
    """Exact edges (no cycle, no noise) with the sensors' hysteresis: the TCP of the tool as designed and of
    the bent and tilted ones within 1e-4 mm of the truth (the pin's radius and the hysteresis cancel, the rim
    is corrected exactly); a tool 4.5 mm too long, or 3.6 mm longer than designed and 2.4 mm longer than the last
    calibration found, is found but not written; 7 mm too short, the first circle
    misses; 9 mm too long, the tip is in the beam where the search starts."""
    cell = load_cell(CELL)
    target = get_target("ur")
    for case in cases(cell, seed=3):
        want = expected(cell, station_for(cell, target, case))
        if case.category in ("as_designed", "bent", "tilted_6deg"):
            assert want.halt is None
            assert np.abs(want.tcp - case.tool[:3, 3]).max() < 1e-4, case.category
        elif case.category == "sensor_frame_error":
            assert want.halt is None
            assert np.linalg.norm(want.tcp - case.tool[:3, 3]) > 0.1  # the frame's error passes into the TCP
        elif case.category in ("tool_too_long", "drifted_since_last"):  # beyond the range of the tool as designed
            assert want.halt == "too_far"
            assert want.tcp[2] == pytest.approx(case.tool[2, 3], abs=1e-4)
        elif case.category == "tip_in_the_beam":
            assert want.halt == "no_tip"
        elif case.category == "steep_axis":
            assert want.halt == "tilt"
        elif case.category.startswith("start_") or case.category == "tool_growing":  # the tool as designed
            assert want.halt is None
        else:  # too short for the first circle, or sensors that never switch
            assert case.category in ("tool_too_short", "sensors_silent") and want.halt == "circle 1"


def test_without_the_rim_correction_a_tilted_pin_is_found_off():
    """The source's tip taken on the axis where the beam first meets the pin: a pin tilted 2 deg in x with
    radius 1.5 mm ends 1.5 sin(2 deg) = 0.05 mm lower at its rim; the reference corrects it (checked by
    breaking it: the uncorrected tip is off by about that)."""
    cell = load_cell(CELL)
    tool = cell.robot.tool.tcp2flange.copy()
    tool[:3, :3] = rotation((0, 1, 0), 2.0) @ tool[:3, :3]
    station = BeamStation(cell.sections["laser"].sensor_frame.matrix(), Pin(tool, 1.5), {"a": "x", "b": "y"})
    want = expected(cell, station)
    assert np.abs(want.tcp - tool[:3, 3]).max() < 1e-4
    rim = 1.5 * math.sin(math.radians(2.0))
    assert rim > 0.05  # what the correction is worth here


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ("depths_mm = [5.0, 15.0]", "depths_mm = [5.0, 6.0]", "laser.depths_mm"),
        ("pin_radius_mm = 1.5", "pin_radius_mm = 0.1", "laser.pin_radius_mm"),
        ("circle_speed_mm_s = 10.0", "circle_speed_mm_s = 100.0", "laser.circle_speed_mm_s"),
        ('abb = "diLaserY"', 'abb = "dilaserx"', "laser.beam_y.abb"),
        ("circle_mm = 10.0", "circle_mm = 6.0", "laser.circle_mm"),
        ("clearance_mm = 8.0", "clearance_mm = 2.0", "laser.clearance_mm"),
        ('ur = "pin_tcp", kuka = 3, abb = "tPin"', 'ur = "pin_tcp", kuka = 3', "laser.production_tool.abb"),
        ("kuka = 3, abb", 'kuka = "TOOL_DATA[3]", abb', "laser.production_tool.kuka"),
        ("kuka = 3, abb", "kuka = 17, abb", "laser.production_tool.kuka"),
        ('abb = "tPin"', 'abb = "MODULE"', "laser.production_tool.abb"),
        ('abb = "tPin"', 'abb = "lsr_guess"', "laser.production_tool.abb"),
        ('ur = "pin_tcp"', "ur = 3", "laser.production_tool.ur"),
        ('ur = "pin_tcp"', 'ur = "pin tcp"', "laser.production_tool.ur"),
        ("cog_mm = [0.0, 0.0, 70.0]", "cog_mm = [0.0, 0.0, 70.0]\nnumbered = { kuka = 4 }", "production_tool.kuka"),
        ("safe_height_mm = 100.0", "safe_height_mm = 10.0", "laser.safe_height_mm"),
        ("zone_mm = 5.0", "zone_mm = 8.0", "cell.motion.zone_mm"),
    ],
)
def test_a_laser_section_that_cannot_work_is_refused_naming_its_key(tmp_path, old, new, key):
    """Steps too close for an axis, a pin no beam sees, circles faster than the slowest controller looks
    (KUKA: 100 mm/s x 12 ms = 1.2 mm > half the radius), one RAPID signal named twice in other cases, circles
    that cannot cross both beams, a search starting below the tip; a target without its production tool, one
    that is not the target's form (a KRL tool number 1..16, a RAPID or URScript name that is no reserved word
    and not the program's own), a KRL production tool other than the cell's numbered tool; a safe pose below the
    search's top; a blend longer than half the way down to the circles' start: exit 2, the key named, nothing
    written."""
    from click.testing import CliRunner

    from codegen.cli import main

    text = FilePath(CELL).read_text()
    assert old in text
    cell = tmp_path / "laser.toml"
    cell.write_text(text.replace(old, new))
    result = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2 and key in result.output, result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("*.script"))
