"""codegen run --signal: an input named by its number lies within the controller's range (targets/<t>.toml)."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from codegen.cli import main

UR = """def p():
  if get_standard_digital_in(7):
    textmsg("seven on")
  else:
    textmsg("seven off")
  end
end
"""
KRL = "DEF p()\n  INT n\n  n = 1\nEND\n"


def _run(tmp_path, name: str, text: str, signal: str):
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, ["run", str(program), "--signal", signal])


def test_an_input_within_the_range_is_on_at_the_start(tmp_path):
    result = _run(tmp_path, "p.script", UR, "standard_digital_in[7]=1")
    assert result.exit_code == 0 and "seven on" in result.output


@pytest.mark.parametrize(
    ("name", "text", "signal", "shown"),
    [
        ("p.script", UR, "standard_digital_in[8]=1", "standard_digital_in[0] to standard_digital_in[7]"),
        ("p.script", UR, "standard_digital_in[99]=1", "standard_digital_in[0] to standard_digital_in[7]"),
        ("p.script", UR, "standard_digital_in[-1]=1", "standard_digital_in[0] to standard_digital_in[7]"),
        ("p.src", KRL, "$IN[0]=1", "$IN[1] to $IN[4096]"),
        ("p.src", KRL, "$IN[4097]=0", "$IN[1] to $IN[4096]"),
    ],
)
def test_an_input_past_the_controllers_range_is_refused(tmp_path, name, text, signal, shown):
    result = _run(tmp_path, name, text, signal)
    assert result.exit_code == 2, result.output
    assert f"--signal '{signal}'" in result.output and shown in result.output and "Traceback" not in result.output


def test_the_range_ends_are_inputs_and_an_alias_is_the_programs(tmp_path):
    assert _run(tmp_path, "p.src", KRL, "$IN[4096]=1").exit_code == 0
    assert _run(tmp_path, "p.src", KRL, "$IN[1]=1").exit_code == 0
    assert _run(tmp_path, "p.script", UR, "standard_digital_in[0]=1").exit_code == 0
    assert _run(tmp_path, "p.src", KRL, "gripper_closed=1").exit_code == 0  # a SIGNAL alias: not a number to check
