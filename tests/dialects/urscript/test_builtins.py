"""URScript built-ins of the manual's script directory: pose math, motion, I/O, timing, tool and payload."""

from __future__ import annotations

import math

import numpy as np
import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load
from codegen.poses import matrix_from_ur
from codegen.robot.arms import find_arm

HOME = [180, -90, 90, -90, -90, 0]  # deg, a UR10e standing upright


def prog(body: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"


def run(body: str, **kwargs):
    return load(prog(body), "t.script").run({}, **kwargs)


def numbers(text: str) -> list[float]:
    return [float(v) for v in text.strip("p[]").split(",")]


def test_the_manuals_examples_of_pose_math():
    """The examples of the URScript manual's pages pose_add, rpy2rotvec and rotvec2rpy."""
    got = run(
        'textmsg("", pose_add(p[.2,.5,.1,1.57,0,0], p[.2,.5,.6,1.57,0,0]))\n'
        'textmsg("", rpy2rotvec([3.14,1.57,0]))\ntextmsg("", rotvec2rpy([3.14,1.57,0]))'
    ).messages
    assert numbers(got[0]) == pytest.approx([0.4, 1.0, 0.7, 3.14, 0, 0], abs=1e-5)
    assert numbers(got[1]) == pytest.approx([2.22153, 0.00177, -2.21976], abs=1e-5)
    assert numbers(got[2]) == pytest.approx([-2.80856, -0.16202, 0.9], abs=1e-5)


def test_pose_add_multiplies_the_rotations_in_order_and_pose_sub_undoes_it():
    a, b = [0.1, 0.2, 0.3, 0.4, -0.2, 0.3], [0.3, -0.2, 0.1, -0.5, 0.2, 1.0]
    got = run(f'textmsg("", pose_add(p{a}, p{b}))\ntextmsg("", pose_add(pose_sub(p{a}, p{b}), p{b}))').messages
    ma, mb = matrix_from_ur(a), matrix_from_ur(b)
    added = matrix_from_ur(numbers(got[0]))
    assert np.allclose(added[:3, :3], ma[:3, :3] @ mb[:3, :3], atol=1e-5)  # p_3.R = p_1.R * p_2.R
    assert np.allclose(added[:3, 3], ma[:3, 3] + mb[:3, 3], atol=1e-3)
    assert numbers(got[1]) == pytest.approx(a, abs=1e-5)


def test_interpolate_pose_point_dist_normalize():
    a, b = [0.1, 0.2, 0.3, 0.0, 0.0, 0.0], [0.5, 0.2, 0.0, 0.0, 0.0, 1.0]
    got = run(
        f'textmsg("", interpolate_pose(p{a}, p{b}, 0.5))\ntextmsg("", interpolate_pose(p{a}, p{b}, 1))\n'
        f'textmsg("", point_dist(p{a}, p{b}))\ntextmsg("", normalize([3, 4]))\ntextmsg("", norm([3, 4]))'
    ).messages
    assert numbers(got[0]) == pytest.approx([0.3, 0.2, 0.15, 0.0, 0.0, 0.5], abs=1e-6)
    assert numbers(got[1]) == pytest.approx(b, abs=1e-6)
    assert float(got[2]) == pytest.approx(0.5)
    assert numbers(got[3]) == pytest.approx([0.6, 0.8]) and got[4] == "5"


def test_math_functions():
    got = run(
        'textmsg("", pow(2, 10))\ntextmsg("", log(10, 1000))\ntextmsg("", r2d(acos(0.5)))\n'
        'textmsg("", ceil(1.2))\ntextmsg("", length([1, 2, 3]))\ntextmsg("", str_len("abcd"))'
    ).messages
    assert [float(v) for v in got] == pytest.approx([1024, 3, 60, 2, 3, 4], abs=1e-4)


def test_arithmetic_on_arrays_is_element_wise():
    got = run(
        "a = [1, 2, 3]\nb = [0.5, 0.5, 0.5]\n"
        'textmsg("", a + b)\ntextmsg("", 2 * a)\ntextmsg("", a - b)\ntextmsg("", a * b)\ntextmsg("", a / 2)\n'
        'textmsg("", [[1, 2], [3, 4]] * 0.5)'
    ).messages
    assert got == [
        "[1.5, 2.5, 3.5]",
        "[2, 4, 6]",
        "[0.5, 1.5, 2.5]",
        "[0.5, 1, 1.5]",
        "[0.5, 1, 1.5]",
        "[[0.5, 1], [1.5, 2]]",
    ]
    with pytest.raises(RunError, match=r"t\.script:2:\d+: \+ of arrays of 2 and 3 elements"):
        run("x = [1, 2] + [1, 2, 3]")
    with pytest.raises(RunError, match=r"t\.script:2:\d+: a matrix product is not modelled"):
        run("x = [[1, 2], [3, 4]] * [1, 2]")


def test_movep_and_the_settings_of_each_move():
    trace = run(
        "set_tcp(p[0, 0, 0.1, 0, 0, 0])\nset_target_payload(2.0, [0, 0, 0.05])\n"
        "movel(p[0.5, 0.1, 0.4, 0, 3.1416, 0], 1.0, 0.2, 0, 0.01)\n"
        "movep(p[0.5, 0.2, 0.4, 0, 3.1416, 0], a=1.1, v=0.1, r=0.02)\n"
        "movej(p[0.5, 0.3, 0.4, 0, 3.1416, 0], t=2.5)"
    )
    linear, process, joint = trace.moves
    assert (linear.kind, process.kind, joint.kind) == ("linear", "process", "joint")
    assert linear.settings["a"] == 1.0 and linear.settings["v"] == pytest.approx(0.2)
    assert linear.settings["r"] == pytest.approx(0.01) and linear.settings["t"] == 0.0
    assert process.settings["a"] == pytest.approx(1.1) and process.settings["r"] == pytest.approx(0.02)
    assert joint.settings["t"] == 2.5 and joint.end_time - process.end_time == pytest.approx(2.5)
    assert linear.settings["load"] == pytest.approx((2.0, 0.0, 0.0, 50.0, *(0.0,) * 6))  # no inertia given
    assert joint.settings["tcp"] == pytest.approx((0.0, 0.0, 0.1, 0.0, 0.0, 0.0))


def test_speedl_with_a_time_moves_at_that_speed_and_without_until_the_stop():
    trace = run(
        "movel(p[0.5, 0.2, 0.4, 0, 3.1416, 0])\nspeedl([0, 0, -0.05, 0, 0, 0], 0.5, 2.0)\n"
        'speedl([0.1, 0, 0, 0, 0, 0], 0.5)\nsleep(1.5)\nstopl(1.0)\ntextmsg("", get_actual_tcp_pose())'
    )
    _start, timed, held = trace.moves
    assert np.allclose(timed.tcp2base[:3, 3], [500, 200, 300], atol=1e-3)  # 0.05 m/s down for 2 s
    assert np.allclose(held.tcp2base[:3, 3], [650, 200, 300], atol=1e-3)  # 0.1 m/s along x for 1.5 s
    assert held.settings["t"] == pytest.approx(1.5) and held.settings["move"] == "speedl"
    assert numbers(trace.messages[0])[:3] == pytest.approx([0.65, 0.2, 0.3], abs=1e-5)


def test_speedj_servoj_and_the_kinematics_with_the_arm():
    trace = run(
        "q = get_inverse_kin(p[0.6, 0.2, 0.4, -2.2214, 2.2214, 0], qnear=[3.14, -1.57, 1.57, -1.57, -1.57, 0])\n"
        'textmsg("", get_forward_kin(q))\nmovej(q)\nspeedj([0.1, 0, 0, 0, 0, 0], 1.0, 0.5)\n'
        "servoj([3.2, -1.57, 1.57, -1.57, -1.57, 0], t=0.1)",
        arm=find_arm("UR10e"),
        start_joints=HOME,
    )
    assert numbers(trace.messages[0]) == pytest.approx([0.6, 0.2, 0.4, -2.2214, 2.2214, 0.0], abs=1e-5)
    moved, turned, servo = trace.moves
    assert turned.joints[0] - moved.joints[0] == pytest.approx(math.degrees(0.05), abs=1e-6)
    assert servo.joints[0] == pytest.approx(math.degrees(3.2)) and servo.settings["t"] == pytest.approx(0.1)


def test_a_first_move_to_a_pose_goes_from_where_the_arm_stands_and_movel_takes_joints():
    trace = run(
        "movel(p[0.6, 0.2, 0.4, -2.2214, 2.2214, 0])\nmovel([3.2, -1.57, 1.57, -1.57, -1.57, 0])\n"
        'textmsg("", get_target_tcp_pose())',
        arm=find_arm("UR10e"),
        start_joints=HOME,
    )
    first, second = trace.moves
    assert first.kind == "linear" and np.allclose(first.tcp2base[:3, 3], [600, 200, 400], atol=1e-3)
    assert second.kind == "linear" and second.joints[0] == pytest.approx(math.degrees(3.2), abs=1e-3)
    with pytest.raises(RunError, match=r"t\.script:2:\d+: movel to joint positions needs the arm's kinematics"):
        run("movel([3.2, -1.57, 1.57, -1.57, -1.57, 0])")


def test_outputs_are_signal_events_and_inputs_nothing_provides_are_named_simulated():
    trace = run(
        "set_configurable_digital_out(2, True)\nset_tool_digital_out(1, False)\nset_standard_digital_out(5, True)\n"
        "x = get_configurable_digital_in(3)\ny = get_tool_analog_in(0)\nz = get_standard_digital_in(1)\n"
        'textmsg("", x)\ntextmsg("", get_configurable_digital_out(2))'
    )
    assert [(o.name, o.value, o.line) for o in trace.outputs] == [
        ("configurable_digital_out[2]", True, 2),
        ("tool_digital_out[1]", False, 3),
        ("standard_digital_out[5]", True, 4),
    ]
    assert trace.simulated == ["configurable_digital_in[3]", "tool_analog_in[0]", "standard_digital_in[1]"]
    assert trace.messages == ["False", "True"]
    signalled = load(prog('x = get_tool_digital_in(0)\ntextmsg("", x)'), "t.script").run(
        {}, signals={"tool_digital_in[0]": True}
    )
    assert signalled.messages == ["True"]


def test_timing_tool_and_payload_queries():
    trace = run(
        'set_tcp(p[0, 0, 0.2, 0, 0, 0])\nmovel(p[0.4, 0.1, 0.3, 0, 3.0, 0])\ntextmsg("", get_steptime())\n'
        'textmsg("", get_tcp_force())\ntextmsg("", get_tcp_offset())\ntextmsg("", get_target_tcp_pose())\n'
        'set_flag(3, True)\ntextmsg("", get_flag(3))'
    )
    assert trace.messages[:3] == ["0.002", "[0, 0, 0, 0, 0, 0]", "p[0, 0, 0.2, 0, 0, 0]"]
    assert numbers(trace.messages[3]) == pytest.approx([0.4, 0.1, 0.3, 0, 3.0, 0], abs=1e-5)
    assert trace.messages[4] == "True"


def test_installation_settings_of_an_exported_program_are_accepted():
    trace = run(
        "set_standard_analog_input_domain(0, 1)\nset_tool_analog_input_domain(1, 1)\nset_analog_outputdomain(0, 0)\n"
        "set_tool_voltage(24)\nset_input_actions_to_default()\nset_gravity([0.0, 0.0, 9.82])\n"
        'set_safety_mode_transition_hardness(1)\nset_payload(1.0)\ntextmsg("ok")'
    )
    assert trace.messages == ["ok"]
    with pytest.raises(RunError, match=r"t\.script:2:\d+: set_tool_voltage takes 1 arguments, got 2"):
        run("set_tool_voltage(24, 1)")


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (
            "x = 1\nforce_mode(p[0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 5, 0, 0, 0], 2, [1, 1, 1, 1, 1, 1])",
            r"^t\.script:3:\d+: force_mode is not modelled: force control",
        ),
        ("if False:\n  path_offset_enable()\nend", r"^t\.script:3:\d+: path_offset_enable is not modelled"),
        ("x = pose_dist(p[0, 0, 0, 0, 0, 0], p[0, 0, 0, 0, 0, 0])", r"^t\.script:2:\d+: pose_dist is not modelled"),
        ("frobnicate(2)", r"^t\.script:2:\d+: frobnicate is not defined"),
        ("thread t():\n  sync()\nend\nt()", r"^t\.script:5:\d+: t is a thread: start it with run t\(\)"),
    ],
)
def test_what_is_not_modelled_is_refused_at_load_by_name(body, message):
    with pytest.raises(RunError, match=message):
        load(prog(body), "t.script")


def test_a_step_limit_and_a_move_limit_keep_what_ran():
    body = "while True:\n  movel(p[0.5, 0.1, 0.4, 0, 3.1416, 0])\n  movel(p[0.5, 0.2, 0.4, 0, 3.1416, 0])\nend"
    trace = run(body, max_moves=5)
    assert len(trace.moves) == 5 and "5 moves" in trace.ended
    trace = run(body, max_seconds=3.0)
    assert trace.clock >= 3.0 and "3 s" in trace.ended and len(trace.moves) >= 5
    from codegen.dialects.core.values import StepLimitError

    with pytest.raises(StepLimitError) as info:
        run(body, step_limit=50)
    assert len(info.value.trace.moves) > 10 and "step limit 50" in info.value.trace.ended


def test_a_wait_nothing_ends_stops_at_the_time_limit():
    trace = run(
        "movel(p[0.5, 0.1, 0.4, 0, 3.1416, 0])\nwhile not get_standard_digital_in(2):\n  sync()\nend", max_seconds=2
    )
    assert len(trace.moves) == 1 and trace.clock == pytest.approx(2.0, abs=0.01) and "time limit" in trace.ended


def test_analog_outputs_registers_stopj_and_popup():
    trace = run(
        "set_standard_analog_out(1, 0.25)\nwrite_output_float_register(30, 1.5)\n"
        "write_output_boolean_register(70, True)\n"
        'textmsg("", read_output_float_register(30))\ntextmsg("", read_output_boolean_register(70))\n'
        'textmsg("", get_standard_analog_in(0))\nstopj(2.0)\npopup("check the gripper", title="Cell", blocking=True)',
    )
    assert trace.messages == ["1.5", "True", "0", "check the gripper"]
    assert trace.simulated == ["standard_analog_in[0]"]
    with pytest.raises(RunError, match=r"t\.script:2:\d+: set_standard_analog_out\(n, f\) takes f in \[0; 1\]"):
        run("set_standard_analog_out(0, 2.0)")
    with pytest.raises(RunError, match=r"t\.script:2:\d+: write_output_boolean_register takes True or False"):
        run("write_output_boolean_register(70, 1)")


def test_a_move_beyond_an_axis_limit_is_refused_naming_the_first_such_axis():
    over = math.radians(361.0)
    for joints, axis in (([0, -1.57, over, -1.57, -1.57, 0], 3), ([0, -over, 1.57, -1.57, over, 0], 2)):
        text = f"movej([{', '.join(repr(v) for v in joints)}])"
        with pytest.raises(RunError, match=rf"axis {axis} at -?361\.000 deg is beyond its limits \[-360, 360\] of"):
            run(text, arm=find_arm("UR10e"), start_joints=HOME)
    inside = math.radians(359.9)
    trace = run(f"movej([0, -1.57, {inside!r}, -1.57, -1.57, 0])", arm=find_arm("UR10e"), start_joints=HOME)
    assert trace.moves[0].joints[2] == pytest.approx(359.9, abs=1e-4)
