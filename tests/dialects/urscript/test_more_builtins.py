"""URScript built-ins that public programs call: the target waypoint, speeds at rest, tool contact, whether a pose
has an inverse kinematics solution, bits to an integer, a wrench seen from another frame, random numbers, and the
operator's typed answers; what stays refused is refused by what it is."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load
from codegen.robot.arms import find_arm
from codegen.sim.operator import Operator

HOME = "movej([0, -1.57, 1.57, -1.57, -1.57, 0])"


def run(body: str, **kwargs):
    text = "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"
    return load(text, "t.script").run({}, **kwargs)


def test_the_target_waypoint_is_the_last_moves_target_and_speeds_are_zero_at_rest():
    body = f"{HOME}\nw = get_target_waypoint()\nt = get_target_tcp_pose()\ntextmsg(point_dist(w, t))\n"
    body += "textmsg(get_target_tcp_speed())\ntextmsg(get_actual_joint_speeds())\ntextmsg(get_target_joint_speeds())"
    messages = run(body, arm=find_arm("UR5e")).messages  # a move to joints: its pose from the kinematics
    assert messages == ["0", "[0, 0, 0, 0, 0, 0]", "[0, 0, 0, 0, 0, 0]", "[0, 0, 0, 0, 0, 0]"]


def test_no_contact_is_ever_detected_without_contact_forces():
    assert run(f"{HOME}\ntextmsg(tool_contact(direction=[0, 0, -0.1, 0, 0, 0]))").messages == ["0"]


def test_whether_a_pose_has_an_inverse_kinematics_solution():
    body = "textmsg(get_inverse_kin_has_solution(p[0.4, 0, 0.3, 0, 3.14, 0]))\n"
    body += "textmsg(get_inverse_kin_has_solution(p[4, 0, 0.3, 0, 3.14, 0]))"
    assert run(body, arm=find_arm("UR5e")).messages == ["True", "False"]
    with pytest.raises(RunError, match=r"needs the arm's kinematics"):
        run(body)


def test_binary_list_to_integer_reads_the_first_element_as_the_lowest_bit():
    body = "textmsg(binary_list_to_integer([True, False, True]))\ntextmsg(binary_list_to_integer([False, True]))"
    assert run(body).messages == ["5", "2"]
    with pytest.raises(RunError, match=r"takes a list of booleans"):
        run("binary_list_to_integer([1, 0])")


def test_a_wrench_seen_from_a_frame_turned_and_moved():
    # the frame 0.1 m up and turned 90 deg about z; F = (1, 2, 3) N and no torque at the old origin: in the new
    # axes F = (2, -1, 3), and about the new origin M = R^T (-p x F) = R^T (0.2, -0.1, 0) = (-0.1, -0.2, 0)
    body = "textmsg(wrench_trans(p[0, 0, 0.1, 0, 0, 1.5707963], [1, 2, 3, 0, 0, 0]))"
    numbers = run(body).messages[0].strip("[]").split(", ")
    assert [round(float(v), 5) for v in numbers] == [2.0, -1.0, 3.0, -0.1, -0.2, 0.0]


def test_random_numbers_lie_in_zero_to_one_and_repeat_from_run_to_run():
    body = "i = 0\nwhile i < 5:\n  textmsg(random())\n  i = i + 1\nend"
    first, second = run(body).messages, run(body).messages
    assert first == second
    assert len(set(first)) == 5
    assert all(0.0 <= float(v) < 1.0 for v in first)


def test_the_operators_typed_answers():
    body = 'n = request_integer_from_primary_client("How many?")\ntextmsg(n + 1)\n'
    body += 'x = request_float_from_primary_client("How far?")\ntextmsg(x * 2)\n'
    body += 's = request_string_from_primary_client("Name?")\ntextmsg(str_cat("hi ", s))'
    assert run(body, devices=[Operator(["12", "0.25", "Ada"])]).messages[1::2] == ["13", "0.5", "hi Ada"]
    with pytest.raises(RunError, match=r"the operator's answer 'many' is not an integer"):
        run(body, devices=[Operator(["many"])])


@pytest.mark.parametrize(
    ("call", "what"),
    [
        ('modbus_add_signal("10.0.0.2", 255, 5, 1, "out1")', "Modbus devices are not simulated"),
        ('rpc = rpc_factory("xmlrpc", "http://10.0.0.3:8080")', "network peers are not simulated"),
    ],
)
def test_what_stays_refused_is_refused_by_what_it_is(call, what):
    with pytest.raises(RunError, match=rf"is not modelled: {what}"):
        run(call)
