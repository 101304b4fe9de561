"""Loads from shape against closed forms written out here, and the controllers' forms of them."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from codegen.poses import rotmat_from_quat, rotmat_from_zyx_deg
from codegen.world import loads
from codegen.world.solids import translation


def turned(axis: str, angle_deg: float, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    rotation = {"z": [[c, -s, 0], [s, c, 0], [0, 0, 1]], "y": [[c, 0, s], [0, 1, 0], [-s, 0, c]]}[axis]
    out = translation(x, y, z)
    out[:3, :3] = rotation
    return out


def test_box_off_the_flange_parallel_axis_terms():
    m, (a, b, c), (dx, dz) = 2.0, (0.1, 0.2, 0.05), (0.01, 0.08)  # kg, m, m
    load = loads.box(m, (100.0, 200.0, 50.0), translation(10.0, 0.0, 80.0))
    own = [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]
    assert np.diag(load.inertia_cog) == pytest.approx(own, rel=1e-12)
    expected = np.array([
        [own[0] + m * dz * dz, 0.0, -m * dx * dz],
        [0.0, own[1] + m * (dx * dx + dz * dz), 0.0],
        [-m * dx * dz, 0.0, own[2] + m * dx * dx],
    ])
    assert load.about_flange() == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_cylinder_lying_along_flange_x():
    m, r, h, dz = 1.5, 0.04, 0.3, 0.12
    load = loads.cylinder(m, 40.0, 300.0, turned("y", 90.0, z=120.0))  # its axis along the flange's x
    assert load.about_flange() == pytest.approx(np.diag([
        m * r * r / 2 + m * dz * dz,
        m * (3 * r * r + h * h) / 12 + m * dz * dz,
        m * (3 * r * r + h * h) / 12,
    ]), abs=1e-15)


def test_controller_forms_of_a_turned_box():
    m = 3.0
    load = loads.box(m, (300.0, 100.0, 60.0), turned("z", 30.0, 0.0, 0.0, 90.0))
    jx, jy, jz = m * (0.1**2 + 0.06**2) / 12, m * (0.3**2 + 0.06**2) / 12, m * (0.3**2 + 0.1**2) / 12
    kuka = load.principal_zyx()
    assert (kuka["M"], kuka["X"], kuka["Y"], kuka["Z"]) == pytest.approx((3.0, 0.0, 0.0, 90.0), abs=1e-12)
    assert (kuka["A"], kuka["B"], kuka["C"]) == pytest.approx((30.0, 0.0, 0.0), abs=1e-9)
    assert (kuka["JX"], kuka["JY"], kuka["JZ"]) == pytest.approx((jx, jy, jz), rel=1e-12)
    mass, cog, aom, ix, iy, iz = load.principal_quaternion()
    assert aom == pytest.approx((math.cos(math.radians(15)), 0.0, 0.0, math.sin(math.radians(15))), abs=1e-12)
    assert cog == pytest.approx((0.0, 0.0, 90.0), abs=1e-12)
    assert (mass, ix, iy, iz) == pytest.approx((3.0, jx, jy, jz), rel=1e-12)
    _, cog_m, inertia = load.tensor_at_cog()
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    ixx, iyy = jx * c * c + jy * s * s, jx * s * s + jy * c * c  # R diag(jx, jy) R^T about z
    ixy = (jx - jy) * c * s
    assert cog_m == pytest.approx([0.0, 0.0, 0.09])
    assert inertia == pytest.approx([ixx, iyy, jz, ixy, 0.0, 0.0], rel=1e-12, abs=1e-15)


def test_a_load_needs_mass():
    with pytest.raises(ValueError, match="positive mass"):
        loads.box(0.0, (1.0, 1.0, 1.0), np.eye(4))


def test_two_point_masses_combined_about_their_common_centre():
    """m1 m2 / (m1 + m2) d^2 about the axes across the line joining them (the reduced mass), none along it."""
    load = loads.combined(loads.point(1.0, (0.0, 0.0, 0.0)), loads.point(3.0, (0.0, 0.0, 400.0)))
    assert load.mass == 4.0 and load.cog_mm == pytest.approx([0.0, 0.0, 300.0])
    reduced = 1.0 * 3.0 / 4.0 * 0.4**2
    assert load.inertia_cog == pytest.approx(np.diag([reduced, reduced, 0.0]), abs=1e-15)


def test_a_tools_cylinder_from_the_flange_to_a_tilted_tcp():
    """A cylinder of radius 25 mm along a TCP 200 mm out, tilted 90 deg to the flange's x: its axis moment is about
    x; the declared centre of gravity is kept (the controller is told that one)."""
    tool = SimpleNamespace(
        tcp2flange=translation(200.0, 0.0, 0.0), mass_kg=2.0, cog_mm=(90.0, 0.0, 5.0), radius_mm=25.0, box_mm=None
    )
    load = loads.of_tool(tool, shaped=True)
    side, axis = 2.0 * (3 * 0.025**2 + 0.2**2) / 12, 2.0 * 0.025**2 / 2
    assert load.cog_mm == pytest.approx([90.0, 0.0, 5.0])
    assert load.inertia_cog == pytest.approx(np.diag([axis, side, side]), abs=1e-15)
    boxed = loads.of_tool(SimpleNamespace(**{**vars(tool), "box_mm": (40.0, 60.0)}), shaped=True)
    assert sorted(np.diag(boxed.inertia_cog)) == pytest.approx(
        sorted([2.0 * (0.04**2 + 0.06**2) / 12, 2.0 * (0.04**2 + 0.2**2) / 12, 2.0 * (0.06**2 + 0.2**2) / 12])
    )
    assert loads.of_tool(tool, shaped=False).inertia_cog == pytest.approx(np.zeros((3, 3)))


def test_a_payload_in_the_tool_frame_moved_to_the_flange():
    tcp2flange = turned("z", 90.0, 0.0, 0.0, 100.0)  # the tool frame turned 90 deg about z, 100 mm out
    part = loads.box(2.0, (100.0, 200.0, 50.0), translation(10.0, 0.0, 20.0))
    moved = part.moved(tcp2flange)
    assert moved.cog_mm == pytest.approx([0.0, 10.0, 120.0], abs=1e-12)
    own = np.diag(part.inertia_cog)
    assert np.diag(moved.inertia_cog) == pytest.approx([own[1], own[0], own[2]])  # x and y swap places
    back = moved.expressed_in(tcp2flange)
    assert back.cog_mm == pytest.approx(part.cog_mm) and back.inertia_cog == pytest.approx(part.inertia_cog)


def test_the_controllers_forms_read_back():
    load = loads.box(3.0, (300.0, 100.0, 60.0), turned("z", 30.0, 5.0, -4.0, 90.0))
    kuka = load.principal_zyx()
    angles = rotmat_from_zyx_deg(kuka["A"], kuka["B"], kuka["C"])
    moments = (kuka["JX"], kuka["JY"], kuka["JZ"])
    read = loads.from_principal(kuka["M"], (kuka["X"], kuka["Y"], kuka["Z"]), angles, moments)
    assert read.flat() == pytest.approx(load.flat(), abs=1e-15)
    mass, cog, aom, *moments = load.principal_quaternion()
    read = loads.from_principal(mass, cog, rotmat_from_quat(aom), moments)
    assert read.flat() == pytest.approx(load.flat(), abs=1e-15)
    mass, cog_m, tensor = load.tensor_at_cog()
    assert loads.from_tensor(mass, [v * 1000 for v in cog_m], tensor).flat() == pytest.approx(load.flat(), abs=1e-15)


def test_remembered_results_are_the_functions_own():
    """Each input's own result however many came before: inputs equal but for one number, or only in the sign of a
    zero (equal by ==, apart in the result), and more inputs than are kept."""
    made = []

    def make(*numbers):
        made.append(numbers)
        return tuple(math.copysign(1.0, v) * (i + 1) for i, v in enumerate(numbers))

    remembered = loads.Remembered(make)
    inputs = [(1.0, 2.0, 0.0), (1.0, 2.0, -0.0), (1.0, 3.0, 0.0), (1.0, 2.0)]
    inputs += [(float(k), 0.5) for k in range(loads.REMEMBERED_LOADS + 10)]
    for numbers in inputs * 2:
        assert remembered(*numbers) == make(*numbers)
    assert remembered(1.0, 2.0, -0.0)[2] == -3.0
    remembered(7.0, 0.5)
    before = len(made)
    remembered(7.0, 0.5)
    assert len(made) == before  # found again, not made again
