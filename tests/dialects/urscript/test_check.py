"""codegen check of URScript: every finding with file:line, and the field's checks (waits, TCP, speeds)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects import get_dialect
from codegen.dialects.core.files import CheckOptions, SourceFile
from codegen.robot.arms import find_arm

from .test_language import POLYSCOPE

BAD = """def bad():
  movej([0, -1.57, 1.57, -1.57, -1.57, 0], v=4.0)
  set_tcp(p[0, 0, 0.1, 0, 0, 0])
  force_mode(p[0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 5, 0, 0, 0], 2, [1, 1, 1, 1, 1, 1])
  x = y + 1
  frobnicate(3)
  while not get_standard_digital_in(2):
    sync()
  end
  speedj([0.1, 0.2, 3.5, 0, 0, 0], 0.5, 1.0)
  socket_open("10.0.0.2", 3000)
end
"""


def findings(text: str, name: str = "t.script", arm=None) -> list[tuple[int, str, str]]:
    found = get_dialect("urscript").check_files([SourceFile(name, text)], CheckOptions(arm=arm))
    return [(f.line, f.severity, f.code) for f in found]


def test_every_finding_of_a_file_with_its_line():
    assert findings(BAD) == [
        (2, "warning", "motion-before-tcp"),
        (4, "unsupported", "unsupported"),
        (5, "error", "undefined-name"),
        (6, "error", "undefined-function"),
        (7, "warning", "wait-without-timeout"),
        (11, "unsupported", "unsupported"),
    ]


def test_speeds_over_the_arms_joints():
    with_arm = [f for f in findings(BAD, arm=find_arm("UR10e")) if f[2] == "speed-over-arm"]
    assert with_arm == [(2, "warning", "speed-over-arm"), (10, "warning", "speed-over-arm")]
    assert not [f for f in findings(BAD, arm=find_arm("UR3e")) if f[2] == "speed-over-arm" and f[0] == 2]


def test_a_wait_that_counts_or_a_program_that_sets_its_tcp_first_is_clean():
    text = """def ok():
  set_tcp(p[0, 0, 0.1, 0, 0, 0])
  movej([0, -1.57, 1.57, -1.57, -1.57, 0])
  waited = 0
  while not get_standard_digital_in(2) and waited < 250:
    sync()
    waited = waited + 1
  end
end
"""
    assert findings(text) == []


def test_motion_in_a_function_called_before_set_tcp():
    text = "def p():\n  def go():\n    movel(p[0.4, 0, 0.3, 0, 3, 0])\n  end\n  go()\n"
    text += "  set_tcp(p[0, 0, 0, 0, 0, 0])\nend\n"
    assert findings(text) == [(3, "warning", "motion-before-tcp")]


def test_the_polyscope_style_program_is_clean():
    assert findings(POLYSCOPE, "cell.script") == []


def test_a_syntax_error_and_a_load_error():
    assert findings("def p():\n  x = (1 +\nend\n")[0][1:] == ("error", "syntax")
    assert findings("def p():\n  thread t(a):\n    sync()\n  end\nend\n") == [(2, "error", "load")]


def test_the_command_reports_all_files_and_exits_by_the_worst(tmp_path):
    (tmp_path / "bad.script").write_text(BAD)
    (tmp_path / "cell.script").write_text(POLYSCOPE)
    (tmp_path / "wait.script").write_text("def w():\n  while not get_standard_digital_in(1):\n    sync()\n  end\nend\n")
    runner = CliRunner()
    clean = runner.invoke(main, ["check", str(tmp_path / "cell.script")])
    assert clean.exit_code == 0 and clean.output.startswith("clean: 1 file"), clean.output
    warned = runner.invoke(main, ["check", str(tmp_path / "wait.script")])
    assert warned.exit_code == 1 and "wait.script:2:3: warning:" in warned.output, warned.output
    every = runner.invoke(main, ["check", str(tmp_path), "--json"])
    assert every.exit_code == 2
    data = json.loads(every.output)
    assert [f["file"].rsplit("/", 1)[-1] for f in data["findings"]] == ["bad.script"] * 6 + ["wait.script"]
    assert data["counts"] == {"error": 2, "unsupported": 2, "warning": 3} and data["exit"] == 2


def test_a_wait_that_also_ends_on_an_operators_stop_is_not_reported():
    text = "def w():\n  while read_input_integer_register(46) == 0 and not read_input_boolean_register(64):\n"
    text += "    sync()\n  end\nend\n"
    assert findings(text) == []


def test_the_generated_programs_check_clean():
    generated = Path(__file__).resolve().parents[3] / "generated"
    result = CliRunner().invoke(main, ["check", *sorted(str(p) for p in generated.glob("*/ur"))])
    assert result.exit_code == 0 and result.output.startswith("clean: "), result.output


def _runs(body: str) -> str:
    """The program's run: '' when it finishes, else the error it stops on."""
    from codegen.dialects.core.values import RunError
    from codegen.dialects.urscript.interpreter import load

    try:
        load(body, "t.script").run({})
    except RunError as exc:
        return str(exc)
    return ""


def _prog(body: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"


FUNCTION = "def f(a, b=2):\n  return a + b\nend\n"


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("f()", "no value for its parameter a"),
        ("f(1, 2, 3)", "f takes 2 arguments, got 3"),
        ("f(1, c=2)", "f has no parameter c"),
        ("f(1, a=2)", "argument a given twice"),
        ("f(b=1)", "no value for its parameter a"),
    ],
)
def test_a_call_that_does_not_fit_the_function_is_found_by_check_as_run_stops_on_it(call, message):
    text = _prog(f"{FUNCTION}x = {call}")
    assert message in _runs(text)
    found = [(line, severity, code, m) for line, severity, code, m in _messages(text) if code == "arity"]
    assert [(line, severity) for line, severity, _c, _m in found] == [(5, "error")] and message in found[0][3]


@pytest.mark.parametrize("call", ["f(1)", "f(1, 2)", "f(a=1)", "f(b=3, a=1)", "f(1, b=3)"])
def test_a_call_that_fits_is_clean(call):
    text = _prog(f"{FUNCTION}x = {call}\ntextmsg(x)")
    assert _runs(text) == ""
    assert [f for f in findings(text) if f[2] == "arity"] == []


@pytest.mark.parametrize(
    "lines",
    ["l = [1, 2, 3]\nx = l[3]", "l = [1, 2, 3]\nl[-1] = 0", "l = [0, 0, 0]\nl = [1, 2]\nx = l[3]", "l = []\nx = l[0]"],
)
def test_a_literal_index_beyond_a_list_is_found_by_check_as_run_stops_on_it(lines):
    text = _prog(f"{lines}\ntextmsg(l)")
    assert "out of range" in _runs(text)
    assert [(f[0], f[1]) for f in findings(text) if f[2] == "index"] == [(1 + len(lines.splitlines()), "error")]


@pytest.mark.parametrize(
    "lines",
    [
        "l = [1, 2, 3]\nx = l[2]\nl[0] = 4",
        "l = [1]\nl = [1, 2, 3]\nx = l[2]",  # the longer list assigned last
        "def h():\n  return [1, 2, 3, 4, 5, 6]\nend\nl = [1, 2, 3]\nl = h()\nx = l[5]",  # another length at run
        "def g(l):\n  return l[4]\nend\nl = [1, 2]\nx = g([1, 2, 3, 4, 5])",  # a parameter of that name
    ],
)
def test_an_index_within_the_list_or_of_a_list_of_unknown_length_is_clean(lines):
    text = _prog(f"{lines}\ntextmsg(l)")
    assert _runs(text) == ""
    assert [f for f in findings(text) if f[2] == "index"] == []


@pytest.mark.parametrize(
    ("lines", "at"),
    [
        ("x = q + 1\nq = 2", 2),
        ("q = q + 1", 2),  # the assignment reads it first
        ("if True:\n  x = q\nend\nq = 1", 3),
        ("def g():\n  x = q\n  q = 1\nend\ng()", 3),  # a function's own variable
    ],
)
def test_a_variable_read_before_it_is_assigned_is_found_by_check_as_run_stops_on_it(lines, at):
    text = _prog(f"{lines}\ntextmsg(1)")
    assert "undefined variable q" in _runs(text)
    assert [(f[0], f[1]) for f in findings(text) if f[2] == "read-before-assign"] == [(at, "warning")]


@pytest.mark.parametrize(
    "lines",
    [
        "q = 1\nx = q",
        "i = 0\nwhile i < 2:\n  if i > 0:\n    x = q\n  end\n  q = i\n  i = i + 1\nend",  # a later turn reads it
        "def g():\n  global q = 5\nend\ng()\nx = q\nq = 1",  # a global another function assigns
        "def g():\n  q = 1\nend\nq = 2\ng()",
    ],
)
def test_a_variable_assigned_before_it_is_read_is_clean(lines):
    text = _prog(f"{lines}\ntextmsg(1)")
    assert _runs(text) == ""
    assert [f for f in findings(text) if f[2] == "read-before-assign"] == []


def _messages(text: str) -> list[tuple[int, str, str, str]]:
    found = get_dialect("urscript").check_files([SourceFile("t.script", text)], CheckOptions())
    return [(f.line, f.severity, f.code, f.message) for f in found]
