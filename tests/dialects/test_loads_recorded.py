"""Each interpreter records the load its controller has, in one form (mass, centre of gravity mm, the tensor at it in
flange axes kg m2), from the controller's own: URScript's tensor, KRL's principal axes as angles, RAPID's as a
quaternion with a payload in the tool frame. The expected tensors are written out here by hand."""

from __future__ import annotations

import math

import pytest

from codegen.dialects.rapid.interpreter import load as load_rapid
from codegen.dialects.urscript.interpreter import load as load_ur

from .krl.helpers import program as krl_program

C30, S30 = math.cos(math.radians(30.0)), math.sin(math.radians(30.0))
JX, JY, JZ = 0.02, 0.05, 0.04  # principal moments, kg m2


def turned_30_about_z() -> list[float]:
    """diag(JX, JY, JZ) turned 30 deg about z, R J R^T by hand: [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]."""
    return [JX * C30 * C30 + JY * S30 * S30, JX * S30 * S30 + JY * C30 * C30, JZ, (JX - JY) * C30 * S30, 0.0, 0.0]


def test_urscript_takes_the_tensor_at_the_centre_of_gravity_in_metres():
    script = (
        "def prog():\n  set_target_payload(2.0, [0.01, -0.02, 0.05], [0.03, 0.04, 0.05, 0.001, -0.002, 0.003])\n"
        "  movel(p[0.5, 0.1, 0.4, 0, 3.1416, 0])\n  set_target_payload(1.0, [0, 0, 0.05])\n"
        "  movel(p[0.5, 0.2, 0.4, 0, 3.1416, 0])\nend\n"
    )
    first, second = load_ur(script, "t.script").run({}).moves
    assert first.settings["load"] == pytest.approx((2.0, 10.0, -20.0, 50.0, 0.03, 0.04, 0.05, 0.001, -0.002, 0.003))
    assert second.settings["load"] == pytest.approx((1.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))


def test_krl_load_principal_axes_turned_by_a_b_c():
    body = (
        f"$LOAD = {{M 3.0,CM {{X 0.0,Y 0.0,Z 90.0,A 30.0,B 0.0,C 0.0}},J {{X {JX},Y {JY},Z {JZ}}}}}\n"
        "PTP {X 500,Y 0,Z 600,A 0,B 90,C 0,S 2,T 35}"
    )
    (move,) = krl_program(body).run({}).moves
    assert move.settings["load"] == pytest.approx((3.0, 0.0, 0.0, 90.0, *turned_30_about_z()), abs=1e-8)


def test_krl_numbered_load_with_its_inertia():
    body = "$LOAD = LOAD_DATA[2]\nPTP {X 500,Y 0,Z 600,A 0,B 90,C 0,S 2,T 35}"
    inputs = {"LOAD_DATA[2]": (3.0, 0.0, 0.0, 90.0, 30.0, 0.0, 0.0, JX, JY, JZ)}
    (move,) = krl_program(body).run(inputs).moves
    assert move.settings["load"] == pytest.approx((3.0, 0.0, 0.0, 90.0, *turned_30_about_z()), abs=1e-8)


RAPID = """MODULE T
CONST robtarget p0 := [[400, 0, 500], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
PERS tooldata grip := [TRUE, [[0, 0, 100], [1, 0, 0, 0]], [1.0, [0, 0, 50], [{q1}, 0, 0, {q4}], {jx}, {jy}, {jz}]];
PERS loaddata part := [2.0, [10, 0, 20], [1, 0, 0, 0], 0.001, 0.002, 0.003];
PROC main()
  MoveL p0, v100, fine, grip;
  GripLoad part;
  MoveL p0, v100, fine, grip;
  GripLoad load0;
  MoveL p0, v100, fine, grip;
ENDPROC
ENDMODULE
"""


def test_rapid_tool_load_axes_of_moment_and_a_payload_in_the_tool_frame():
    text = RAPID.format(q1=math.cos(math.radians(15.0)), q4=math.sin(math.radians(15.0)), jx=JX, jy=JY, jz=JZ)
    alone, held, released = load_rapid(text, "t.mod").run({}).moves
    tool = [1.0, 0.0, 0.0, 50.0, *turned_30_about_z()]
    assert alone.settings["load"] == pytest.approx(tool, abs=1e-7)
    assert released.settings["load"] == pytest.approx(tool, abs=1e-7)
    # the part 100 mm further along z (the TCP) plus its own cog: (10, 0, 120) mm in the flange frame; the common
    # centre (1 * (0, 0, 50) + 2 * (10, 0, 120)) / 3; each part's tensor plus m (|d|^2 E - d d^T), d in metres
    cog = (20.0 / 3.0, 0.0, (50.0 + 240.0) / 3.0)
    d_tool = [(0.0 - cog[0]) / 1000, 0.0, (50.0 - cog[2]) / 1000]
    d_part = [(10.0 - cog[0]) / 1000, 0.0, (120.0 - cog[2]) / 1000]
    parts = ((1.0, d_tool, turned_30_about_z()), (2.0, d_part, [0.001, 0.002, 0.003, 0.0, 0.0, 0.0]))
    xx = sum(i[0] + m * d[2] ** 2 for m, d, i in parts)
    yy = sum(i[1] + m * (d[0] ** 2 + d[2] ** 2) for m, d, i in parts)
    zz = sum(i[2] + m * d[0] ** 2 for m, d, i in parts)
    xy = sum(i[3] for _, _, i in parts)
    xz = sum(-m * d[0] * d[2] for m, d, _ in parts)
    assert held.settings["load"] == pytest.approx((3.0, *cog, xx, yy, zz, xy, xz, 0.0), abs=1e-7)


def test_krl_loads_apart_only_in_their_axes_each_recorded_as_its_own():
    """Two loads of the same mass, centre and moments, turned apart (each run's result is remembered by its numbers,
    never by the first of them), and the first set again."""
    turned = f"$LOAD = {{M 3.0,CM {{X 0.0,Y 0.0,Z 90.0,A 30.0,B 0.0,C 0.0}},J {{X {JX},Y {JY},Z {JZ}}}}}\n"
    straight = f"$LOAD = {{M 3.0,CM {{X 0.0,Y 0.0,Z 90.0,A 0.0,B 0.0,C 0.0}},J {{X {JX},Y {JY},Z {JZ}}}}}\n"
    move = "PTP {X 500,Y 0,Z 600,A 0,B 90,C 0,S 2,T 35}\n"
    moves = krl_program(turned + move + straight + move + turned + move).run({}).moves
    want_turned = pytest.approx((3.0, 0.0, 0.0, 90.0, *turned_30_about_z()), abs=1e-8)
    want_straight = pytest.approx((3.0, 0.0, 0.0, 90.0, JX, JY, JZ, 0.0, 0.0, 0.0), abs=1e-8)
    assert [m.settings["load"] for m in moves] == [want_turned, want_straight, want_turned]


def test_rapid_payload_follows_the_tcp_of_each_move():
    """The same tool load and payload with two TCPs: the payload's place in the flange frame moves with the TCP."""
    text = RAPID.format(q1=1.0, q4=0.0, jx=0.0, jy=0.0, jz=0.0).replace(
        "GripLoad load0;", "GripLoad part;\n  MoveL p0, v100, fine, far;\n  MoveL p0, v100, fine, grip;"
    ).replace("PERS loaddata part", "PERS tooldata far := [TRUE, [[0, 0, 200], [1, 0, 0, 0]], [1.0, [0, 0, 50], "
              "[1, 0, 0, 0], 0, 0, 0]];\nPERS loaddata part")
    moves = load_rapid(text, "t.mod").run({}).moves
    # the part's cog (10, 0, 20) in the tool frame: z 120 mm past the flange with the TCP at 100, 220 at 200
    cogs = [m.settings["load"][1:4] for m in moves[1:5]]
    near, far = (20.0 / 3.0, 0.0, (50.0 + 240.0) / 3.0), (20.0 / 3.0, 0.0, (50.0 + 440.0) / 3.0)
    assert cogs == [pytest.approx(c, abs=1e-9) for c in (near, far, near, near)]
