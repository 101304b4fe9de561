"""Program files under bad input: a RAPID index with a fraction, URScript ints past 32 bits wherever they are made,
literals and constant expressions past the controller's numbers and loops that never end found by check, and the
checks' one reading of a number literal."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects.core.files import SourceFile


def _invoke(tmp_path, name: str, text: str, command: str = "run"):
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, [command, str(program)]), program


def _urscript(*lines: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in lines) + "end\n"


def _rapid(data: str, *lines: str) -> str:
    return f"MODULE m\n{data}\nPROC main()\n" + "".join(f"{line}\n" for line in lines) + "ENDPROC\nENDMODULE\n"


# --- RAPID: an index is a whole number ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("lines", "line", "shown"),
    [
        (("a{1.5} := 3;",), 6, "1.5"),  # a store: it went to a{1}
        (("k := 2.5;", 'TPWrite "x" \\Num:=a{k};'), 7, "2.5"),  # a read through a variable: it read a{2}
        (("k := 1.5;", "b{2, k} := 1;"), 7, "1.5"),  # a second subscript
    ],
)
def test_a_rapid_index_with_a_fraction_stops_the_run(tmp_path, lines, line, shown):
    text = _rapid("VAR num a{3};\nVAR num b{2, 2};\nVAR num k;", *lines)
    result, program = _invoke(tmp_path, "frac.mod", text)
    assert result.exit_code == 1, result.output
    assert re.search(rf"{program.name}:{line}:\d+: index {shown} is not a whole number", result.stderr), result.stderr


def test_a_rapid_whole_index_held_in_a_num_still_runs(tmp_path):
    text = _rapid("VAR num a{3};\nVAR num k;", "k := 2;", "a{k} := 7;", 'TPWrite "x" \\Num:=a{2};')
    result, _ = _invoke(tmp_path, "whole.mod", text)
    assert result.exit_code == 0, result.output
    assert "message: x7" in result.output


def test_check_finds_a_rapid_literal_index_with_a_fraction(tmp_path):
    text = _rapid("VAR num a{3};", "a{1.5} := 3;", 'TPWrite "x" \\Num:=a{-2.5};', "a{2} := 1;")
    result, program = _invoke(tmp_path, "frac.mod", text, "check")
    assert result.exit_code == 2, result.output
    assert f"{program.name}:4:1: error: index 1.5 is not a whole number" in result.output
    assert f"{program.name}:5:" in result.output and "index -2.5 is not a whole number" in result.output
    assert ":6:" not in result.output


@pytest.mark.parametrize("command", ["run", "check"])
def test_a_rapid_dimension_with_a_fraction_is_refused(tmp_path, command):
    text = _rapid("CONST num n := 2.5;\nVAR num a{n};", "a{1} := 1;")
    result, program = _invoke(tmp_path, "dim.mod", text, command)
    assert result.exit_code == 2, result.output
    assert f"{program.name}:3:" in result.output + result.stderr
    assert "dimension must be a whole number of at least 1, got 2.5" in result.output + result.stderr


# --- URScript: ints are 32-bit wherever they are made -------------------------------------------------------------
BITS_32 = "binary_list_to_integer gives 4294967295"


@pytest.mark.parametrize(
    ("lines", "says"),
    [
        (("x = -2147483648", "y = -x"), "the negation gives 2147483648"),
        (('y = to_num("99999999999")',), "to_num gives 99999999999"),
        (("x = [2147483647, 1]", "y = x + [1, 1]"), "the + of an element gives 2147483648"),
        (("x = [65536, 1]", "y = x * 65536"), "the * of an element gives 4294967296"),
        (("y = binary_list_to_integer([" + ", ".join(["True"] * 32) + "])",), BITS_32),
    ],
)
def test_urscript_ints_made_past_32_bit_stop_the_run(tmp_path, lines, says):
    """Each ran on as a Python int past the controller's."""
    result, program = _invoke(tmp_path, "int.script", _urscript(*lines, "textmsg(y)"))
    assert result.exit_code == 1, result.output
    assert f"integer overflow: {says}, beyond the controller's 32-bit ints" in result.stderr, result.stderr
    assert f"{program.name}:{1 + len(lines)}:" in result.stderr


def test_urscript_ints_made_within_32_bit_run_on(tmp_path):
    lines = ("x = -2147483647", "textmsg(-x)", 'textmsg(to_num("2147483647"))', "textmsg([2147483646, 0] + [1, 1])")
    result, _ = _invoke(tmp_path, "int.script", _urscript(*lines, "textmsg(binary_list_to_integer([True, True]))"))
    assert result.exit_code == 0, result.output
    for shown in ("2147483647", "2147483647", "[2147483647, 1]", "3"):
        assert f"message: {shown}" in result.output


# --- URScript check: numbers past the controller's, loops that never end -----------------------------------------


def test_check_reports_every_literal_and_constant_expression_past_the_numbers(tmp_path):
    """Loading stops at the first; check lists each, where run would refuse or stop."""
    lines = (
        "a = 2147483648",
        "b = -(-2147483648)",
        "c = 65536 * 65536",
        "d = 1e39",
        "e = 3e38 * 10",
        "f = 2147483647 + 1 - 5",
        "g = -2147483648",  # the least int: a literal still
        "h = 1.5 * 2147483647 * 2",  # a float: within float32
        "textmsg(a)",
    )
    result, program = _invoke(tmp_path, "lits.script", _urscript(*lines), "check")
    assert result.exit_code == 2, result.output
    found = {int(m.group(1)): m.group(2) for m in re.finditer(rf"{program.name}:(\d+):\d+: error: (.*)", result.output)}
    assert found == {
        2: "number 2147483648 is beyond the controller's integers (-2147483648..2147483647, 32-bit) [overflow]",
        3: "integer overflow: the negation gives 2147483648, beyond the controller's 32-bit ints [overflow]",
        4: "integer overflow: the * gives 4294967296, beyond the controller's 32-bit ints [overflow]",
        5: "number 1e39 is beyond the controller's numbers (32-bit floating point: at most 3.402823e+38) [overflow]",
        6: "the * gives 3e+39, which is beyond the controller's numbers"
        " (32-bit floating point: at most 3.402823e+38) [overflow]",
        7: "integer overflow: the + gives 2147483648, beyond the controller's 32-bit ints [overflow]",
    }, result.output


@pytest.mark.parametrize(
    "body",
    [
        ["while True:", "  x = 1", "end"],
        ["while 1:", "  textmsg(1)", "  if x > 2:", "    x = 0", "  end", "end"],
        ["while True:", "  count()", "end"],  # the function it calls takes no time either
    ],
)
def test_check_finds_a_loop_that_never_ends_and_takes_no_time(tmp_path, body):
    """run stops it at the step limit; the controller with a protective stop; check said nothing."""
    text = _urscript("x = 0", *body) + "def count():\n  textmsg(2)\nend\n"
    result, program = _invoke(tmp_path, "loop.script", text, "check")
    assert result.exit_code == 2, result.output
    assert f"{program.name}:3:3: error: the loop never ends and takes no physical time" in result.output
    assert "[runaway-loop]" in result.output


@pytest.mark.parametrize(
    "body",
    [
        ["while True:", "  sync()", "end"],
        ["while True:", "  wait()", "end"],  # a function that sleeps
        ["while True:", "  if get_standard_digital_in(0):", "    break", "  end", "end"],
        ["while True:", "  movej([0, -1.57, 1.57, 0, 1.57, 0])", "end"],
        ["while x < 3:", "  x = x + 1", "end"],  # a condition that changes
        ["while True:", "  halt", "end"],
    ],
)
def test_check_leaves_loops_that_wait_or_end(tmp_path, body):
    text = _urscript("x = 0", *body) + "def wait():\n  sleep(0.1)\nend\n"
    result, _ = _invoke(tmp_path, "loop.script", text, "check")
    assert "runaway-loop" not in result.output, result.output


def test_check_finds_a_runaway_loop_in_a_thread(tmp_path):
    text = "thread poll():\n  while True:\n    x = get_standard_digital_in(1)\n  end\nend\n"
    text += _urscript("t = run poll()", "sleep(1)", "kill t")
    result, program = _invoke(tmp_path, "thread.script", text, "check")
    assert f"{program.name}:2:3: error: the loop never ends" in result.output, result.output


# --- one reading of a number literal for every check ---------------------------------------------------------------


def test_krl_check_reads_a_hexadecimal_literal(tmp_path):
    """'H0' as a divisor was float("'H0'"): a traceback."""
    text = "DEF prog()\n  DECL INT X\n  X = 1 / 'H0'\n  X = 1 / 'H10'\nEND\n"
    result, program = _invoke(tmp_path, "hex.src", text, "check")
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    assert f"{program.name}:3:7: error: division by zero" in result.output
    assert ":4:" not in result.output


def test_the_checks_read_number_literals_in_one_place():
    """dtrans and URScript each had their own _number; RAPID's did not read a negated literal."""
    checks = Path(__file__).resolve().parents[1] / "codegen" / "dialects"
    own = [p for p in checks.glob("*/check*.py") if re.search(r"^def _number\(node", p.read_text(), re.M)]
    assert own == []


def test_dtrans_check_parses_a_file_once(monkeypatch):
    """The common check parsed it, loading parsed it again and dtrans' own check a third time."""
    from codegen.dialects import dialects
    from codegen.dialects.core import parsing

    calls = []
    real = parsing._parse
    monkeypatch.setattr(parsing, "_parse", lambda *a, **k: calls.append(a[2]) or real(*a, **k))
    text = "Int a[3]\na[3] = 1\nTPWrite 0, \"%d %d\", 1\n"
    found = dialects()["dtrans"].check_files([SourceFile("once.prg", text)])
    assert {(f.line, f.code) for f in found} == {(2, "index"), (3, "format")}
    assert calls == ["once.prg"]
