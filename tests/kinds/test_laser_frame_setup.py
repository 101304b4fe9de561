"""The setup program with a reference pin (UR): run against simulated beams lying where the cell does not say, it
finds the sensor frame they lie in, within the error the model gives; a program with a sign or an axis swapped
does not."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from support.programs import sources

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.kinds.laser import frame_setup as fs
from codegen.kinds.laser.budget import FLOAT32_MM, tolerances
from codegen.kinds.laser.frame_solve import solve_frame
from codegen.model.cell import load_cell
from codegen.model.io import signal_name
from codegen.poses import rotmat_from_zyx_deg
from codegen.robot.expect import arm_of
from codegen.sim.beam_station import BeamStation
from codegen.sim.beams import Pin

CELL = "codegen/examples/laser/laser_tcp.toml"


# the bundled cell with a reference pin: its TCP in the flange frame, its radius (the bundled cell names none: verify
# has no cases for the setup program, and every bundled program is verified)
REFERENCE = "reference_tcp_mm = [0.0, 0.0, 150.0]\nreference_radius_mm = 1.5\n"


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    path = tmp_path_factory.mktemp("laser") / "laser_tcp.toml"
    text = Path(CELL).read_text().replace("[laser]\n", "[laser]\n" + REFERENCE, 1)
    path.write_text(text)
    return load_cell(path)


TARGETS = ("ur", "kuka", "abb")


def _setup_source(cell, target="ur"):
    (source,) = [s for s in sources(cell, target, "laser") if s.index == 1]
    return source


def _offset(shift, zyx_deg) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotmat_from_zyx_deg(*zyx_deg)
    out[:3, 3] = shift
    return out


def _run(cell, source, true_frame: np.ndarray, noise: float = 0.0, hysteresis: float = 0.0, seed: int = 0, start=None):
    target = get_target(source.target)
    laser = cell.sections["laser"]
    inputs = {
        signal_name(target, "input", laser.beam_x[target.name]): "x",
        signal_name(target, "input", laser.beam_y[target.name]): "y",
    }
    pin = Pin(fs.reference_tool(laser), laser.reference_radius_mm)
    station = BeamStation(true_frame, pin, inputs, noise=noise, hysteresis=hysteresis, seed=seed)
    return source.load().run(
        {},
        devices=(station,),
        arm=arm_of(cell, target.name),
        start_joints=cell.robot.home[target.name] if start is None else start,
        keep=tuple(fs.FRAME_NAMES.values()),
        signal_cycle_s=target.program["signal_cycle_s"],
        step_limit=4_000_000,
    )


def _bounds(cell, target_name: str, noise: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """How far the found frame may lie from the true one (x, y, z mm; a, b, c deg), from the model: each mean of
    four edges off by up to the calibration's centre tolerance (half a cycle's travel on the circle: the two
    crossings run in opposite directions), each contact by half a cycle's travel in the search (the mean of the
    down and the up edge), propagated through the solve by its first derivatives (each term at its worst sign),
    and float32 on top."""
    laser = cell.sections["laser"]
    target = get_target(target_name)
    tol = tolerances(cell, target, noise)  # a mean of four edges: half a cycle's travel and three sigmas
    contact = laser.search_speed_mm_s * float(target.program["signal_cycle_s"]) / 2 + 6 * noise / math.sqrt(2)
    contact += FLOAT32_MM
    named = laser.sensor_frame.matrix()
    delta, span = fs.step_mm(laser), fs.span_mm(laser)

    def found(v):
        beams = solve_frame(
            (v[0], v[1]), (v[2], v[3]), delta, (v[4], v[5]), (v[6], v[7]), span, laser.reference_radius_mm
        )
        return np.array(fs.xyzabc(fs.frame_found(named, beams)))

    base = np.zeros(8)
    bound = np.array([tol.centre] * 4 + [contact] * 4)
    worst = np.zeros(6)
    for i in range(8):
        h = np.zeros(8)
        h[i] = 1e-4
        worst += np.abs((found(base + h) - found(base - h)) / 2e-4) * bound[i]
    return worst[:3] + FLOAT32_MM, worst[3:] + 1e-4


OFF = [  # the beams where the cell does not say: a shift, a yaw, tilts (mm, deg)
    ((0.25, -0.12, 0.08), (0.3, 0.2, -0.1)),
    ((-0.4, 0.3, -0.2), (-0.5, -0.15, 0.25)),
    ((0.1, 0.35, -0.3), (-0.5, -0.6, 0.5)),
]
# the mutants' case: turned and tilted enough that a sign or an axis swapped shows beyond the bounds on every target
# (KUKA's 12 ms input cycle: a yaw bound of about 1.4 deg; the rim's share rho |s| beyond the height's bound)
MUTANT_OFF = ((0.1, 0.35, -0.3), (1.5, -1.2, 1.0))


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize(("shift", "zyx"), [*OFF, MUTANT_OFF])
def test_the_setup_program_finds_the_sensor_frame(cell, target, shift, zyx):
    laser = cell.sections["laser"]
    named = laser.sensor_frame.matrix()
    true_frame = named @ _offset(shift, zyx)
    trace = _run(cell, _setup_source(cell, target), true_frame)
    assert not trace.halted, trace.halt_message
    got = np.array(trace.kept[fs.FRAME_NAMES["frame"]], dtype=float)
    want = np.array(fs.xyzabc(true_frame))
    position, angles = _bounds(cell, target)
    assert np.all(np.abs(got[:3] - want[:3]) <= position), (got, want, position)
    assert np.all(np.abs(got[3:] - want[3:]) <= angles), (got, want, angles)
    # the frame error it finds is well beyond those bounds: the test tells a found frame from the named one
    assert np.max(np.abs(np.array(fs.xyzabc(named)) - want)[:3] - position) > 0
    assert any(m.startswith(fs.FRAME_FOUND[:26]) for m in trace.messages)


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize(("noise", "seed"), [(0.0, 0), (0.01, 0), (0.01, 1)])
def test_the_sensors_noise_and_hysteresis_stay_within_the_bounds(cell, target, noise, seed):
    """The sensors with a 0.05 mm hysteresis, which the means of in and out, and of down and up, cancel (without
    noise the bounds are tight enough that a contact from the down edge alone, 0.025 mm low, fails), and as verify
    simulates them for the calibration (0.01 mm noise, a fresh draw each cycle): the frame found within the bounds
    with the noise's terms."""
    laser = cell.sections["laser"]
    shift, zyx = OFF[1]
    true_frame = laser.sensor_frame.matrix() @ _offset(shift, zyx)
    trace = _run(cell, _setup_source(cell, target), true_frame, noise=noise, hysteresis=0.05, seed=seed)
    assert not trace.halted, trace.halt_message
    got = np.array(trace.kept[fs.FRAME_NAMES["frame"]], dtype=float)
    want = np.array(fs.xyzabc(true_frame))
    position, angles = _bounds(cell, target, noise)
    assert np.all(np.abs(got[:3] - want[:3]) <= position), (got - want, position)
    assert np.all(np.abs(got[3:] - want[3:]) <= angles), (got - want, angles)


MUTANTS = {  # per target: (the line as generated, the line with a sign or an axis swapped)
    "ur": [
        ("tx = lsr_yaw({m}[2] - {m}[0])", "tx = -lsr_yaw({m}[2] - {m}[0])"),  # the yaw's sign
        ("dx = (-ty * r1 - r2) / det", "dx = (-ty * r2 - r1) / det"),  # x and y of the crossing swapped
        ("dz = ({c}[0] + {c}[1]) / 2 - LSR_RADIUS * norm(sx)", "dz = ({c}[0] + {c}[1]) / 2"),  # no rim
        ("sy = ({c}[3] - {c}[2])", "sy = ({c}[2] - {c}[3])"),  # beam Y's slope reversed
    ],
    "kuka": [
        ("TX = (1.0 - SQRT(1.0 - 4.0 * KX * KX)) / (2.0 * KX)", "TX = -(1.0 - SQRT(1.0 - 4.0 * KX * KX)) / (2.0 * KX)"),
        ("DX = (-TY * R1 - R2) / DET", "DX = (-TY * R2 - R1) / DET"),
        ("DZ = ({c}[1] + {c}[2]) / 2.0 - LSR_RADIUS * ABS(SX)", "DZ = ({c}[1] + {c}[2]) / 2.0"),
        ("SY = ({c}[4] - {c}[3])", "SY = ({c}[3] - {c}[4])"),
    ],
    "abb": [
        ("tx := (1 - Sqrt(1 - 4 * kx * kx)) / (2 * kx);", "tx := -(1 - Sqrt(1 - 4 * kx * kx)) / (2 * kx);"),
        ("dx := (-ty * r1 - r2) / det;", "dx := (-ty * r2 - r1) / det;"),
        ("dz := ({c}{{1}} + {c}{{2}}) / 2 - LSR_RADIUS * Abs(sx);", "dz := ({c}{{1}} + {c}{{2}}) / 2;"),
        ("sy := ({c}{{4}} - {c}{{3}})", "sy := ({c}{{3}} - {c}{{4}})"),
    ],
}


@pytest.mark.parametrize(
    ("target", "old", "new"), [(t, old, new) for t, edits in MUTANTS.items() for old, new in edits]
)
def test_a_setup_program_with_a_sign_or_an_axis_swapped_misses_the_frame(cell, target, old, new):
    names = {"m": fs.FRAME_NAMES["means"], "c": fs.FRAME_NAMES["contacts"]}
    old, new = old.format(**names), new.format(**names)
    source = _setup_source(cell, target)
    text = source.files[0].text
    assert text.count(old) == 1, old
    files = (SourceFile(source.files[0].name, text.replace(old, new)), *source.files[1:])
    mutant = replace(source, files=files)
    shift, zyx = MUTANT_OFF
    true_frame = cell.sections["laser"].sensor_frame.matrix() @ _offset(shift, zyx)
    trace = _run(cell, mutant, true_frame)
    got = np.array(trace.kept[fs.FRAME_NAMES["frame"]], dtype=float)
    want = np.array(fs.xyzabc(true_frame))
    position, angles = _bounds(cell, target)
    assert trace.halted or np.any(np.abs(got[:3] - want[:3]) > position) or np.any(np.abs(got[3:] - want[3:]) > angles)


def test_the_frame_s_float64_solve_recovers_a_known_offset(cell):
    """frame_found from exact means and contacts (frame_derivation's formulas forward) is the true frame."""
    laser = cell.sections["laser"]
    named = laser.sensor_frame.matrix()
    shift, zyx = OFF[0]
    offset = _offset(shift, zyx)
    x, y = offset[:3, 0], offset[:3, 1]
    t_x, t_y = x[1] / x[0], y[0] / y[1]
    s_x, s_y = x[2] / math.hypot(x[0], x[1]), y[2] / math.hypot(y[0], y[1])
    d = offset[:3, 3]

    def chord(cx, cy, t, dx_, dy_):
        return cy + ((cx - dx_) * t - (cy - dy_)) / (1 + t * t)

    delta, span, rho = fs.step_mm(laser), fs.span_mm(laser), laser.reference_radius_mm
    y_x = (chord(0, 0, t_x, d[0], d[1]), chord(delta, 0, t_x, d[0], d[1]))
    x_y = (chord(0, 0, t_y, d[1], d[0]), chord(delta, 0, t_y, d[1], d[0]))
    along_x = span * math.sqrt(1 + t_x * t_x)
    z_x = tuple(d[2] + s_x * t + rho * abs(s_x) for t in (-along_x, along_x))
    z_y = tuple(d[2] + s_y * t + rho * abs(s_y) for t in (-along_x, along_x))  # solve_frame: one span
    beams = solve_frame(y_x, x_y, delta, z_x, z_y, span * math.sqrt(1 + t_x * t_x), rho)
    assert np.allclose(fs.frame_found(named, beams), named @ offset, atol=1e-9)


@pytest.mark.parametrize("target", TARGETS)
def test_a_setup_run_started_away_from_home_stops_before_it_moves(cell, target):
    start = list(cell.robot.home[target])
    start[0] += 10.0  # axis 1 turned 10 deg: a joint move home from there is not the program's to make
    named = cell.sections["laser"].sensor_frame.matrix()
    trace = _run(cell, _setup_source(cell, target), named, start=start)
    assert trace.halted and trace.halt_message == fs.FRAME_START_AWAY, trace.halt_message
    assert not trace.moves


def test_a_reference_pin_too_thick_for_the_setup_circles_is_refused(tmp_path):
    from codegen.model.cell import CellError

    path = tmp_path / "laser_tcp.toml"
    text = Path(CELL).read_text().replace("[laser]\n", "[laser]\n" + REFERENCE.replace("1.5", "2.0"), 1)
    path.write_text(text)
    with pytest.raises(CellError) as info:
        load_cell(path)
    assert "laser.reference_radius_mm: the setup run's circles" in str(info.value)
