"""URScript's deprecated digital I/O of one numbering (0..7 the control box's standard ports, 8..9 the tool's):
controllers still run them, and public programs (the ROS 2 driver's own example) call them."""

from __future__ import annotations

import pytest

from codegen.dialects import get_dialect
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load


def run(body: str, **kwargs):
    text = "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"
    return load(text, "t.script").run({}, **kwargs)


def test_set_digital_out_sets_the_standard_port_below_8_and_the_tool_port_above():
    """set_digital_out was "not defined": the driver's example program was refused at its first line."""
    trace = run("set_digital_out(1, True)\nset_digital_out(9, True)\nset_digital_out(8, False)")
    assert [(o.name, o.value) for o in trace.outputs] == [
        ("standard_digital_out[1]", True), ("tool_digital_out[1]", True), ("tool_digital_out[0]", False)
    ]


def test_get_digital_in_and_out_read_the_same_ports():
    body = "set_digital_out(9, True)\ntextmsg(get_digital_out(9))\ntextmsg(get_digital_out(1))\n"
    body += "textmsg(get_digital_in(3))"
    trace = run(body)
    assert trace.messages == ["True", "False", "False"]
    assert "standard_digital_in[3]" in trace.simulated


@pytest.mark.parametrize("call", ["set_digital_out(10, True)", "set_digital_out(-1, True)", "get_digital_in(10)"])
def test_a_port_beyond_9_is_refused_with_the_range(call):
    with pytest.raises(RunError, match=r"takes an integer 0\.\.9, got"):
        run(call)


def test_check_passes_them():
    source = "def prog():\n  set_digital_out(1, True)\n  textmsg(get_digital_in(8))\nend\n"
    found = get_dialect("urscript").check_files([SourceFile("t.script", source)])
    assert [f for f in found if f.severity == "error"] == []
