"""URScript as the manual's syntax chapters define it: functions with default values, lines continued inside
brackets, Program Label lines, scoping, structs and fields, threads, and PolyScope's exported programs."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load


def prog(body: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"


def msgs(body: str, **kwargs) -> list[str]:
    return load(prog(body), "t.script").run({}, **kwargs).messages


def test_default_parameter_values_and_named_arguments():
    body = """def add(a=1, b=2):
  return a + b
end
def scale(x, k=10):
  return x * k
end
textmsg("", add())
textmsg("", add(5))
textmsg("", add(b=10))
textmsg("", add(3, b=4))
textmsg("", scale(2))
textmsg("", scale(2, 3))"""
    assert msgs(body) == ["3", "7", "11", "7", "20", "6"]


def test_a_default_is_evaluated_at_each_call_from_the_globals():
    body = """base = 1
def f(a=base + 1):
  return a
end
textmsg("", f())
base = 5
textmsg("", f())"""
    assert msgs(body) == ["2", "6"]


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("f()", r"t\.script:5:\d+: f: no value for its parameter a"),
        ("f(1, 2, 3)", r"f takes 2 arguments, got 3"),
        ("f(1, c=2)", r"f has no parameter c"),
        ("f(1, a=2)", r"f: argument a given twice"),
    ],
)
def test_arguments_that_do_not_fit_the_parameters_are_refused(call, message):
    body = f"def f(a, b=2):\n  return a + b\nend\nx = {call}"
    with pytest.raises(RunError, match=message):
        msgs(body)


def test_expressions_go_on_over_lines_inside_brackets():
    body = """x = [1,
     2,
     3]
q = p[0.1, 0.2,
      0.3, 0, 0, 0]
y = (x[2] +
     4)
textmsg("", norm(x[0] +
                 x[1]))
textmsg("", y)
textmsg("", q)"""
    assert msgs(body) == ["3", "7", "p[0.1, 0.2, 0.3, 0, 0, 0]"]


def test_a_line_end_outside_brackets_still_ends_the_statement():
    with pytest.raises(RunError, match=r"t\.script:2:\d+: syntax error"):
        load(prog("x = 1 +\n  2"), "t.script")


def test_program_label_lines_have_no_effect():
    body = '$ 1 "BeforeStart"\n$ 2 "Robot Program"\n$ 3 "MoveJ"\n$ 4 "Waypoint_1" "breakAfter"\ntextmsg("on")'
    assert msgs(body) == ["on"]


def test_global_and_local_declarations():
    body = """global counter = 0
a = 0
def bump():
  global made
  made = 1
  counter = counter + 1
  local a = 5
  b = 3
end
bump()
bump()
textmsg("", counter)
textmsg("", made)
textmsg("", a)"""
    assert msgs(body) == ["2", "1", "0"]


def test_struct_fields_and_pose_fields():
    body = """s = struct(speed=0.25, name="slow")
s.speed = 0.5
textmsg("", s.speed)
textmsg(s.name)
q = p[0.1, 0.2, 0.3, 0, 0, 0]
q.z = 0.5
textmsg("", q.y)
textmsg("", q)"""
    assert msgs(body) == ["0.5", "slow", "0.2", "p[0.1, 0.2, 0.5, 0, 0, 0]"]
    with pytest.raises(RunError, match=r"t\.script:3:\d+: no field w in struct"):
        msgs("s = struct(a=1)\nx = s.w")


def test_xor_and_critical_sections():
    body = 'enter_critical\ntextmsg("", True xor False)\ntextmsg("", True xor True)\nexit_critical'
    assert msgs(body) == ["True", "False"]


def test_threads_run_join_and_kill():
    body = """done = 0
thread worker():
  sleep(0.1)
  done = 1
end
thread blinker():
  while True:
    sync()
  end
end
h = run worker()
b = run blinker()
join h
kill b
textmsg("", done)"""
    assert msgs(body) == ["1"]


def test_a_leading_assignment_that_fails_is_one_message_at_load():
    with pytest.raises(RunError, match=r"^t\.script:2:\d+: division by zero$"):
        load(prog("x = 1/0\nmovej([0, 0, 0, 0, 0, 0])"), "t.script")


# A program in PolyScope's exported style, written for these tests: installation settings, TCP and payload,
# globals, a default parameter, a bracketed list over lines, step markers, a thread and an endless main loop.
POLYSCOPE = """def cell_program():
  set_standard_analog_input_domain(0, 1)
  set_standard_analog_input_domain(1, 1)
  set_tool_analog_input_domain(0, 1)
  set_tool_analog_input_domain(1, 1)
  set_analog_outputdomain(0, 0)
  set_analog_outputdomain(1, 0)
  set_input_actions_to_default()
  set_tool_voltage(24)
  set_safety_mode_transition_hardness(1)
  set_gravity([0.0, 0.0, 9.82])
  set_tcp(p[0.0, 0.0, 0.150, 0.0, 0.0, 0.0])
  set_target_payload(1.5, [0.0, 0.0, 0.06], [0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
  global cycles = 0
  home_q = [d2r(180), d2r(-90), d2r(90),
            d2r(-90), d2r(-90), d2r(0)]
  pick = p[0.700, 0.200, 0.300,
           -2.2214, 2.2214, 0.0]
  place = p[0.700, -0.200, 0.300, -2.2214, 2.2214, 0.0]
  def approach(target, dz=0.10, speed=0.25):
    movel(pose_trans(target, p[0, 0, -dz, 0, 0, 0]), a=1.2, v=speed)
  end
  def gripper(close=True):
    set_standard_digital_out(0, close)
    sleep(0.3)
  end
  thread watch_light():
    while True:
      set_standard_digital_out(7, cycles % 2 == 0)
      sleep(0.5)
    end
  end
  $ 1 "BeforeStart"
  light = run watch_light()
  $ 2 "Robot Program"
  while True:
    $ 3 "MoveJ"
    $ 4 "Home" "breakAfter"
    movej(home_q, a=1.4, v=1.05)
    $ 5 "Pick"
    approach(pick)
    movel(pick, a=1.2, v=0.1)
    gripper()
    approach(pick, speed=0.5)
    $ 6 "Place"
    approach(place, 0.15)
    movel(place, a=1.2, v=0.1)
    gripper(False)
    approach(place, dz=0.15)
    cycles = cycles + 1
    textmsg("cycle ", cycles)
  end
end
"""


def test_a_polyscope_style_program_runs_with_every_move():
    from codegen.robot.arms import find_arm

    program = load(POLYSCOPE, "cell.script")
    trace = program.run({}, arm=find_arm("UR10e"), start_joints=[180, -90, 90, -90, -90, 0], max_moves=16)
    assert trace.ended is not None and "16 moves" in trace.ended
    assert [m.settings["move"] for m in trace.moves[:8]] == ["movej"] + ["movel"] * 6 + ["movej"]
    assert [m.line for m in trace.moves[1:7]] == [21, 42, 21, 21, 47, 21]
    assert all(m.joints is not None for m in trace.moves)
    first_pick = trace.moves[2]
    assert abs(first_pick.tcp2base[2, 3] - 300.0) < 1e-3 and first_pick.settings["v"] == pytest.approx(0.1)
    assert first_pick.settings["tcp"] == pytest.approx((0.0, 0.0, 0.15, 0.0, 0.0, 0.0))
    assert first_pick.settings["load"] == pytest.approx((1.5, 0.0, 0.0, 60.0, *(0.0,) * 6))
    gripper = [(o.value, o.line) for o in trace.outputs if o.name == "standard_digital_out[0]"]
    assert gripper[:2] == [(True, 24), (False, 24)]
    assert trace.messages[0] == "cycle 1"
