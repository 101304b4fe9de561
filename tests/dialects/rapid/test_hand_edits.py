"""The demo's generated RAPID program with an integrator's hand edits: each edit is in the trace as itself."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.controllers import get_target
from codegen.dialects.rapid.interpreter import load
from codegen.robot.arms import find_arm
from codegen.sim.vision_pc import VisionPC

DEMO = Path(__file__).parents[3] / "generated" / "agv_machine_tending" / "abb" / "agv_machine_tending.mod"
AFTER = "    vis_release;\n"  # the first: right after the move home, before the station is asked for


def run_edited(*lines: str):
    text = DEMO.read_text(encoding="utf-8")
    at = text.index(AFTER) + len(AFTER)
    edited = text[:at] + "".join(f"    {line}\n" for line in lines) + text[at:]
    first_line = text[:at].count("\n") + 1
    reading = {"vis_station": 1, "vis_x": 612.4, "vis_y": -285.0, "vis_theta": 1.8}
    device = VisionPC.for_target(get_target("abb"), reading)
    trace = load(edited, "edited.mod").run(
        {}, devices=[device], arm=find_arm("IRB 1600-10/1.45"), start_joints=[0, 0, 0, 0, 90, 30]
    )
    return trace, first_line


def test_an_acc_set_and_a_vel_set_are_in_the_settings_of_every_later_move():
    trace, line = run_edited("AccSet 50, 100;", "VelSet 50, 800;")
    before, after = trace.moves[0], trace.moves[1:]
    assert "accset" not in before.settings and after
    assert all(m.settings["accset"] == {"acc": 50.0, "ramp": 100.0, "line": line} for m in after)
    assert all(m.settings["velset"]["line"] == line + 1 for m in after)


def test_an_output_a_wait_and_a_message_are_in_the_trace_as_themselves():
    plain, _ = run_edited()
    trace, line = run_edited("Set doLamp;", "WaitTime 2;", 'TPWrite "checked";')
    assert [(o.name, o.value, o.line) for o in trace.outputs if o.name == "doLamp"] == [("doLamp", True, line)]
    assert trace.simulated_io["doLamp"] == "digital output"
    assert trace.messages == ["checked", *plain.messages]
    assert trace.moves[-1].end_time == pytest.approx(plain.moves[-1].end_time + 2.0)
    assert len(trace.moves) == len(plain.moves)
