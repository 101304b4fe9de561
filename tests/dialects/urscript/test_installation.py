"""URScript installation variables given to a run (installation.NAME): globals before the program's own lines."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load

# the laser program's pattern: the installation's pose read first, a move, then the variable written
READ_FIRST = """def prog():
  before = pin_tcp
  textmsg("before: ", before)
  movel(p[0.5, 0.0, 0.4, 0, 3.1416, 0], a=1.2, v=0.25)
  global pin_tcp = p[0.001, 0.002, 0.181, 0, 0, 0]
end
"""


def test_an_installation_variable_is_a_global_the_program_reads_and_writes():
    """Six numbers are a pose (the installation variable's type where it holds a TCP); the program's write goes
    into it, and the run keeps it."""
    program = load(READ_FIRST, "t.script")
    trace = program.run({"installation.pin_tcp": (0.0004, -0.0003, 0.1812, 0.0, 0.0, 0.0)}, keep=("pin_tcp",))
    assert trace.messages == ["before: p[0.0004, -0.0003, 0.1812, 0, 0, 0]"]
    assert len(trace.moves) == 1
    assert [float(v) for v in trace.kept["pin_tcp"].values()] == pytest.approx([0.001, 0.002, 0.181, 0, 0, 0])


def test_a_name_neither_the_program_nor_the_installation_defines_stops_the_run_where_it_is_read():
    """The installation without pin_tcp: the first line's read is an error naming it, before the move."""
    program = load(READ_FIRST, "t.script")
    with pytest.raises(RunError) as error:
        program.run({}, keep=("pin_tcp",))
    message = str(error.value)
    assert message.startswith("t.script:2:") and "undefined variable pin_tcp" in message and "installation" in message
    assert error.value.trace.moves == [] and error.value.trace.messages == []


@pytest.mark.parametrize(
    ("value", "shown"),
    [(3, "3"), (2.5, "2.5"), (True, "True"), ((1.0, 2.0, 3.0), "[1, 2, 3]"), ("cell 4", "cell 4")],
    ids=["int", "float", "bool", "list", "string"],
)
def test_installation_variables_of_every_type(value, shown):
    trace = load('def prog():\n  textmsg("", i_var_1)\nend\n', "t.script").run({"installation.i_var_1": value})
    assert trace.messages == [shown]


def test_the_program_s_own_set_up_assigns_after_the_preamble():
    """A name the program assigns in its own set-up keeps the program's value (its lines run after the preamble);
    a name it assigns later starts from the installation's."""
    text = 'def prog():\n  speed = 0.5\n  textmsg("", speed)\n  textmsg("", count)\n  count = count + 1\nend\n'
    trace = load(text, "t.script").run({"installation.speed": 0.1, "installation.count": 7})
    assert trace.messages == ["0.5", "7"]


def test_an_installation_variable_s_name_is_an_identifier():
    program = load(READ_FIRST, "t.script")
    assert program.unknown_inputs(["installation.pin_tcp", "installation.other", "installation.9x", "pin_tcp"]) == [
        "installation.9x",
        "pin_tcp",
    ]


def test_codegen_run_gives_the_installation_variable(tmp_path):
    path = tmp_path / "t.script"
    path.write_text(READ_FIRST)
    runner = CliRunner()
    given = runner.invoke(main, ["run", str(path), "--input", "installation.pin_tcp=0.0004,-0.0003,0.1812,0,0,0"])
    assert given.exit_code == 0, given.output
    assert "message: before: p[0.0004, -0.0003, 0.1812, 0, 0, 0]" in given.output
    missing = runner.invoke(main, ["run", str(path)])
    assert missing.exit_code == 1
    assert "undefined variable pin_tcp" in missing.output and "after 0 moves" in missing.output
