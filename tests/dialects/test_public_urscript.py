"""URScript as others write it: the `.urscript` suffix, `pass` as a name, and the built-ins of newer controllers
refused by name (never "not defined"). Programs written here for the test, not taken from the public ones."""

from __future__ import annotations

from click.testing import CliRunner

from codegen.cli import main


def _invoke(tmp_path, name: str, text: str, command: str = "run"):
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, [command, str(program)])


def test_a_urscript_file_is_a_ur_program_without_target(tmp_path):
    """It was "cannot tell the target from the suffix" (codegen writes .script; editors name URScript .urscript)."""
    text = 'def greet():\n  textmsg("hi")\nend\n'
    checked = _invoke(tmp_path, "greet.urscript", text, "check")
    assert checked.exit_code == 0, checked.output
    assert "Universal Robots URScript" in checked.output
    ran = _invoke(tmp_path, "greet.urscript", text)
    assert ran.exit_code == 0, ran.output
    assert "message: hi" in ran.output
    folder = tmp_path / "folder"
    folder.mkdir()
    (folder / "greet.urscript").write_text(text, encoding="utf-8")
    in_folder = CliRunner().invoke(main, ["run", str(folder)])
    assert in_folder.exit_code == 0 and "message: hi" in in_folder.output, in_folder.output


def test_pass_is_a_name_where_no_statement_begins(tmp_path):
    """`local pass = ...` was a syntax error at 'pass'."""
    text = (
        "def verdict(ok):\n"
        '  local pass = "ok"\n'
        "  if not ok:\n"
        '    return str_cat(pass, " not")\n'
        "  end\n"
        "  local said = pass\n"
        "  return said\n"
        "end\n"
        "def main():\n"
        "  textmsg(verdict(True))\n"
        "  textmsg(verdict(False))\n"
        "  if True:\n"
        "    pass\n"
        "  end\n"
        "end\n"
        "main()\n"
    )
    result = _invoke(tmp_path, "verdict.script", text)
    assert result.exit_code == 0, result.output
    assert "message: ok\n" in result.output and "message: ok not" in result.output


def test_pass_assigned_at_a_statements_start_is_still_the_statement(tmp_path):
    """The keyword wins where a statement may begin (also after `return`, as statements may share a line): a line
    starting `pass = ` is a syntax error at its `=`."""
    result = _invoke(tmp_path, "p.script", "def p():\n  pass = 1\nend\n", "check")
    assert result.exit_code == 2
    assert "p.script:2:8: error: syntax error" in result.output


def test_newer_controllers_builtins_are_refused_by_name(tmp_path):
    """Each was "is not defined: not a function of the program nor a built-in modelled here"."""
    calls = {
        "torque_command([0, 0, 0, 0, 0, 0], friction_comp=True)": "the arm's dynamics",
        "direct_torque([0, 0, 0, 0, 0, 0])": "the arm's dynamics",
        "m = get_mass_matrix()": "the arm's dynamics",
        "c = get_coriolis_and_centrifugal_torques()": "the arm's dynamics",
        "j = get_jacobian([0, 0, 0, 0, 0, 0])": "the arm's dynamics",
        "d = get_jacobian_time_derivative([0, 0, 0, 0, 0, 0])": "the arm's dynamics",
        "reset_world_model()": "world model of frames",
        'f = get_frame_parent("base")': "world model of frames",
        'q = get_pose("base")': "world model of frames",
        'move_frame("base", p[0, 0, 0, 0, 0, 0], "world")': "world model of frames",
        't = get_rtde_value("actual_execution_time")': "RTDE outputs",
    }
    for number, (call, why) in enumerate(calls.items()):
        name = call.split("(")[0].split("= ")[-1]
        result = _invoke(tmp_path, f"n{number}.script", f"def n():\n  {call}\nend\n", "check")
        assert result.exit_code == 2, (call, result.output)
        assert f"unsupported: {name} is not modelled: " in result.output and why in result.output, result.output
        assert "not defined" not in result.output
        ran = _invoke(tmp_path, f"n{number}.script", f"def n():\n  {call}\nend\n")
        assert ran.exit_code != 0 and f"{name} is not modelled" in ran.stderr, ran.output
