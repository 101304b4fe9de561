"""URScript threads (thread, run, kill, join, sync), movec, inputs and poses at a thread's frame, in the interpreter."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest

from codegen.dialects.core.values import RunError, StepLimitError
from codegen.dialects.urscript.interpreter import load

CELL = "codegen/examples/laser/laser_tcp.toml"
INPUT = "standard_digital_in[2]"


def prog(body: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"


class Gate:
    """A light gate on standard digital input 2: on while the flange is at x >= 5.03 mm (base frame)."""

    switches = frozenset({INPUT})

    def on_wait(self, machine, where):
        return False

    def switch(self, name, t, flange2base):
        if name != INPUT:
            return None
        return None if flange2base is None else bool(flange2base[0, 3] >= 5.03)


def run(body: str, cycle: float | None = 0.012, keep=(), devices=None, step_limit=200_000):
    program = load(prog(body), "t.script")
    return program.run(
        {}, devices=(Gate(),) if devices is None else devices, keep=keep, signal_cycle_s=cycle, step_limit=step_limit
    )


# A thread counting its frames and latching the frame and the TCP's x (mm) of each rising edge of input 2
WATCH = """set_tcp(p[0, 0, 0, 0, 0, 0])
frames = 0
edges = 0
edge_frame = 0
edge_x = 0.0
last = False
thread watch():
  while True:
    global frames = frames + 1
    now = get_standard_digital_in(2)
    if now and not last:
      global edges = edges + 1
      global edge_frame = frames
      global edge_x = get_actual_tcp_pose()[0] * 1000
    end
    global last = now
    sync()
  end
end
movel(p[0, 0, 0, 0, 0, 0], a=1.2, v=0.01)
h = run watch()
movel(p[0.01, 0, 0, 0, 0, 0], a=1.2, v=0.01)
"""


def test_a_thread_sees_an_edge_at_the_first_frame_after_it_with_the_pose_there():
    """From x = 0 to 10 mm at 10 mm/s, starting at 1 s (the first move, from an unknown pose, takes 1 s); frames
    of 12 ms: the thread's first frame is the first cycle after run (1.008 s, cycle 84); the gate switches at
    1.503 s and the thread sees it in the frame of cycle 126 (1.512 s, its 43rd), with the TCP at 5.12 mm."""
    trace = run(WATCH, keep=("frames", "edges", "edge_frame", "edge_x"))
    assert not trace.halted
    kept = trace.kept
    assert kept["edges"] == 1
    assert kept["edge_frame"] == 126 - 84 + 1
    assert float(kept["edge_x"]) == pytest.approx(5.12, abs=1e-4)
    assert kept["frames"] == math.floor(2.0 / 0.012 + 1e-9) - 84 + 1  # every frame up to the move's end (2 s)


def test_a_killed_thread_sees_nothing_more():
    """Killed, the thread runs no more frames: the gate passed twice more is not counted; run again, it is."""
    body = WATCH + "kill h\nmovel(p[0, 0, 0, 0, 0, 0], a=1.2, v=0.01)\nmovel(p[0.01, 0, 0, 0, 0, 0], a=1.2, v=0.01)\n"
    trace = run(body, keep=("frames", "edges"))
    assert trace.kept["edges"] == 1
    assert trace.kept["frames"] == 166 - 84 + 1  # frames 84..166 (1.008 .. 1.992 s): up to the kill at 2 s
    again = (
        body
        + "h = run watch()\nmovel(p[0, 0, 0, 0, 0, 0], a=1.2, v=0.01)\nmovel(p[0.01, 0, 0, 0, 0, 0], a=1.2, v=0.01)\n"
    )
    assert run(again, keep=("edges",)).kept["edges"] == 2


def test_without_a_switching_device_a_thread_runs_each_2_ms_frame_while_the_program_spends_time():
    """An ordinary run (no signal cycle): the e-Series frame; sleep and sync() of the program give the thread
    its frames, one per sync(); statements alone give none; sleep in the thread skips frames."""
    body = """n = 0
thread count():
  while True:
    global n = n + 1
    sync()
  end
end
h = run count()
x = 1
textmsg("", n)
sleep(0.1)
textmsg("", n)
sync()
sync()
textmsg("", n)
kill h
m = 0
thread slow():
  while True:
    global m = m + 1
    sleep(0.01)
  end
end
h = run slow()
sleep(0.1)
kill h
textmsg("", m)"""
    assert run(body, cycle=None, devices=()).messages == ["0", "50", "52", "10"]


def test_join_waits_for_the_thread_and_its_return_ends_it():
    body = """k = 0
thread three():
  while k < 3:
    global k = k + 1
    sync()
  end
  return False
end
h = run three()
join h
textmsg("", k)
join h
kill h
textmsg("done")"""
    trace = run(body, cycle=None, devices=())
    assert trace.messages == ["3", "done"]


def test_halt_in_a_thread_stops_the_program_and_its_message_is_the_operators():
    body = """thread stopper():
  sync()
  textmsg("stopped by the thread")
  halt
end
h = run stopper()
sleep(1)
textmsg("never")"""
    trace = run(body, cycle=None, devices=())
    assert trace.halted and trace.halt_message == "stopped by the thread"
    assert "never" not in trace.messages


def test_a_thread_that_never_gives_up_its_frame_stops_the_program():
    """The manual's scheduling: a thread must use physical time (sync, sleep) or end within its frame."""
    body = """x = 0
thread spin():
  while True:
    global x = x + 1
  end
end
h = run spin()
sleep(0.1)"""
    with pytest.raises(RunError, match=r"t\.script:4:\d+: thread spin ran \d+ statements within one controller frame"):
        run(body, cycle=None, devices=())


def test_the_step_limit_still_applies_to_a_program_with_threads():
    body = """thread tick():
  while True:
    sync()
  end
end
h = run tick()
sleep(100)"""
    with pytest.raises(StepLimitError):
        run(body, cycle=None, devices=(), step_limit=5000)


def test_runs_are_deterministic_and_leave_no_python_threads_behind():
    before = threading.active_count()
    results = [run(WATCH, keep=("frames", "edge_x")).kept for _ in range(3)]
    assert results[0] == results[1] == results[2]
    with pytest.raises(RunError):
        run("thread bad():\n  x = [1]\n  y = x[3]\nend\nh = run bad()\nsleep(1)", cycle=None, devices=())
    run("thread t():\n  halt\nend\nh = run t()\nsleep(1)", cycle=None, devices=())
    assert threading.active_count() == before


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("thread t(a):\n  sync()\nend", r"t\.script:2:\d+: thread t: a thread cannot take parameters"),
        ("thread t():\n  sync()\nend\nh = run t(1)", r"t\.script:5:\d+: run t\(\): a thread takes no arguments"),
        ("h = run nowhere()", r"t\.script:2:\d+: run nowhere\(\): nowhere is not defined"),
        ("def f():\n  return 1\nend\nh = run f()", r"t\.script:5:\d+: run f\(\): f is a function, not a thread"),
        ("thread t():\n  sync()\nend\nthread t():\n  sync()\nend", r"t\.script:5:\d+: t is defined twice"),
        ("kill 5", r"t\.script:2:\d+: kill takes a thread's handle"),
        ("join [1]", r"t\.script:2:\d+: join takes a thread's handle"),
        ("thread t():\n  sync()\nend\nh = run t()\nkill h\nkill h", r"t\.script:7:\d+: kill: the thread t was killed"),
        (
            "thread t():\n  movel(p[0, 0, 0, 0, 0, 0])\nend\nh = run t()\nsleep(1)",
            r"t\.script:3:\d+: movel from a thread",
        ),
        ("x = get_standard_digital_in(8)", r"t\.script:2:\d+: get_standard_digital_in\(n\) takes an integer 0\.\.7"),
        ("x = get_standard_digital_in(2.0)", r"t\.script:2:\d+: get_standard_digital_in\(n\) takes an integer"),
        ("x = get_standard_digital_in()", r"t\.script:2:\d+: get_standard_digital_in\(n\) takes one argument"),
        ("x = get_standard_digital_in(1, 2)", r"t\.script:2:\d+: get_standard_digital_in\(n\) takes one argument"),
        ("sleep(-1)", r"t\.script:2:\d+: sleep time must be"),
        ("sync(1)", r"t\.script:2:\d+: sync\(\) takes no arguments"),
        ("x = get_actual_tcp_pose()", r"t\.script:2:\d+: get_actual_tcp_pose: the arm's pose is not known"),
    ],
)
def test_misuse_is_refused_naming_the_line(body, message):
    with pytest.raises(RunError, match=message):
        run(body, cycle=None, devices=())


START = "set_tcp(p[0, 0, 0, 0, 0, 0])\nmovel(p[0.01, 0, 0, 0, 0, 0], a=1.2, v=0.01)\n"


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0], mode=2)", r"movec mode must be 0"),
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0], mode=True)", r"movec mode must be 0"),
        ("movec(p[0, 0, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0])", r"movec: .* lie on one line"),
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[0.01, 0, 0, 0, 0, 0])", r"movec: .* lie on one line"),  # a full circle
        ("movec(p[0, 0.01, 0, 0, 0, 0])", r"movec needs pose_to"),
        ("movec([0, 0, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0])", r"movec pose_via as joint positions"),
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0], speed=1)", r"movec has no parameter speed"),
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0], v=0)", r"movec needs a > 0, v > 0"),
        ("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 0], 1.2, 0.1, 0, 0, 1)", r"movec takes at most 6"),
    ],
)
def test_movec_misuse_is_refused_naming_the_line(call, message):
    with pytest.raises(RunError, match=r"t\.script:4:\d+: " + message):
        run(START + call, cycle=None, devices=())


def _sample(call: str, frame: int) -> tuple:
    """A half circle of radius 10 mm about the base's origin, from (10, 0) through (0, 10) at 10 mm/s (the first
    move from an unknown pose takes 1 s), frames of 10 ms: the pose the thread reads in its frame `frame`."""
    body = (
        START
        + f"""seen = p[0, 0, 0, 0, 0, 0]
frames = 0
thread sample():
  while True:
    global frames = frames + 1
    if frames == {frame}:
      global seen = get_actual_tcp_pose()
    end
    sync()
  end
end
h = run sample()
{call}
kill h
"""
    )
    trace = run(body, cycle=0.01, keep=("seen",))
    seen = [float(v) for v in trace.kept["seen"].values()]
    return trace, np.array(seen[:3]) * 1000, np.array(seen[3:])


def test_movec_runs_the_arc_through_its_via_point_at_its_speed():
    """31.4 mm at 10 mm/s; at 1.5 s (frame 50: the first is 1.01 s) the TCP is 0.5 rad round the circle."""
    trace, position, rotvec = _sample("movec(p[0, 0.01, 0, 1, 2, 3], p[-0.01, 0, 0, 0, 0, 0], a=1.2, v=0.01)", 50)
    assert trace.moves[-1].kind == "circular"
    assert trace.moves[-1].end_time == pytest.approx(1.0 + math.pi, abs=1e-6)
    assert position == pytest.approx([10 * math.cos(0.5), 10 * math.sin(0.5), 0.0], abs=1e-4)
    assert rotvec == pytest.approx([0, 0, 0], abs=1e-6)  # mode 0 from and to the same orientation: held
    assert trace.moves[-1].tcp2base[:3, 3] == pytest.approx([-10, 0, 0], abs=1e-4)


def test_movec_mode_0_interpolates_the_orientation_and_mode_1_turns_it_with_the_tangent():
    """Mode 0 to pose_to turned 1 rad about z: at 0.5 rad of the pi-rad arc, 1 rad x 0.5 / pi; mode 1 keeps the
    orientation to the arc's tangent: turned with it, 0.5 rad there and pi at the end (pose_to's ignored)."""
    _, _, rotvec = _sample("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 1], a=1.2, v=0.01, r=0, mode=0)", 50)
    assert rotvec == pytest.approx([0, 0, 0.5 / math.pi], abs=1e-5)
    trace, _, rotvec = _sample("movec(p[0, 0.01, 0, 0, 0, 0], p[-0.01, 0, 0, 0, 0, 1], a=1.2, v=0.01, r=0, mode=1)", 50)
    assert rotvec == pytest.approx([0, 0, 0.5], abs=1e-5)
    end = trace.moves[-1].tcp2base
    assert end[:3, :3] == pytest.approx(np.diag([-1.0, -1.0, 1.0]), abs=1e-6)
