"""The interpreters hold values as the controllers do: a literal past the controller's numbers refused at its line,
an overflow an error of the program (not inf), URScript ints 32-bit, a KRL CHAR array's length kept, a name declared
twice refused, and check finding statically what run finds."""

from __future__ import annotations

import re

import pytest
from click.testing import CliRunner

from codegen.cli import main


def _invoke(tmp_path, name: str, text: str, command: str = "run", *options: str):
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, [command, str(program), *options]), program


def _says(result, location: str, message: str) -> bool:
    """run says "FILE:LINE:COL: message", check "FILE:LINE:COL: error: message" (or warning)."""
    pattern = rf"{re.escape(location)}: (?:error: |warning: )?{re.escape(message)}"
    return re.search(pattern, result.stderr + result.output) is not None


def _urscript(*lines: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in lines) + "end\n"


def _krl(decls: str, *lines: str) -> str:
    return f"DEF prog()\n{decls}\n" + "".join(f"{line}\n" for line in lines) + "END\n"


def _rapid(*lines: str) -> str:
    return "MODULE m\nPROC main()\n" + "".join(f"{line}\n" for line in lines) + "ENDPROC\nENDMODULE\n"


@pytest.mark.parametrize("command", ["run", "check"])
@pytest.mark.parametrize(
    ("name", "text", "line", "says"),
    [
        ("big.script", _urscript("x = 1e999", "textmsg(x)"), "2:7", "number 1e999 is beyond the controller's numbers"),
        ("big.mod", _rapid("VAR num x;", "x := 1E39;"), "4:6", "number 1E39 is beyond the controller's numbers"),
        ("big.src", _krl("DECL REAL X", "X = 5E38"), "3:5", "number 5E38 is beyond the controller's numbers"),
        ("digits.script", _urscript("x = " + "9" * 5000), "2:7", "number 99999999999999999999... has more digits"),
        ("int.script", _urscript("x = 2147483648"), "2:7", "number 2147483648 is beyond the controller's integers"),
        ("int.src", _krl("DECL INT I", "I = 2147483648"), "3:5", "number 2147483648 is beyond the controller's"),
    ],
)
def test_a_literal_past_the_controllers_numbers_is_refused_at_its_line(tmp_path, command, name, text, line, says):
    """1e999 ran as inf; 2147483648 as a Python int that grows without bound."""
    result, program = _invoke(tmp_path, name, text, command)
    assert result.exit_code == 2, result.output
    assert _says(result, f"{program.name}:{line}", says), result.output


def test_the_smallest_integers_are_literals_still(tmp_path):
    result, _ = _invoke(tmp_path, "low.script", _urscript("x = -2147483648", "textmsg(x)", "textmsg(2147483647)"))
    assert result.exit_code == 0, result.output
    assert "message: -2147483648" in result.output and "message: 2147483647" in result.output


@pytest.mark.parametrize(
    ("name", "text", "line"),
    [
        ("ovf.script", _urscript("x = 1e30", "y = x * x * x", "textmsg(y)"), 3),
        ("ovf.src", _krl("DECL REAL X", "X = 1E30", "X = X * X * X"), 4),
        ("ovf.mod", _rapid("VAR num x := 1E30;", "x := x * x * x;", 'TPWrite "x" \\Num:=x;'), 4),
    ],
)
def test_a_result_past_float32_is_an_error_of_the_program(tmp_path, name, text, line):
    """x * x * x ran on as inf, with numpy's warning line on the terminal."""
    result, program = _invoke(tmp_path, name, text)
    assert result.exit_code == 1, result.output
    assert f"{program.name}:{line}:1: arithmetic overflow" in result.stderr or (
        f"{program.name}:{line}:3: arithmetic overflow" in result.stderr
    ), result.stderr
    assert "RuntimeWarning" not in result.stderr and "inf" not in result.output


@pytest.mark.parametrize(
    ("expression", "symbol", "value"),
    [("x + 1", "+", 2147483648), ("-x - 2", "-", -2147483649), ("x * 2", "*", 4294967294)],
)
def test_urscript_ints_are_32_bit(tmp_path, expression, symbol, value):
    """2147483647 + 1 was 2147483648, a Python int that grows without bound."""
    result, program = _invoke(tmp_path, "int.script", _urscript("x = 2147483647", f"y = {expression}", "textmsg(y)"))
    assert result.exit_code == 1, result.output
    assert f"{program.name}:3:" in result.stderr
    assert f"integer overflow: the {symbol} gives {value}, beyond the controller's 32-bit ints" in result.stderr


def test_urscript_ints_within_32_bit_and_floats_run_on(tmp_path):
    text = _urscript("x = 2147483646", "textmsg(x + 1)", "textmsg(x * 10.0)", "textmsg(-x - 2)")
    result, _ = _invoke(tmp_path, "int.script", text)
    assert result.exit_code == 0, result.output
    assert "message: 2147483647" in result.output and "message: -2147483648" in result.output
    assert "message: 21474836000" in result.output


@pytest.mark.parametrize("command", ["run", "check"])
def test_a_krl_char_array_holds_its_length(tmp_path, command):
    """DECL CHAR S[10] held a text of any length."""
    text = _krl("DECL CHAR S[10]\nDECL CHAR T[10]", 'T[] = "0123456789"', 'S[] = "01234567890"')
    result, program = _invoke(tmp_path, "chars.src", text, command)
    assert result.exit_code == 2, result.output
    assert _says(result, f"{program.name}:5:1", "type error: a text of 11 characters does not fit CHAR[10]")


def test_a_krl_char_array_refuses_a_longer_text_made_at_run_time(tmp_path):
    text = _krl("DECL CHAR S[3]\nDECL CHAR T[5]", 'T[] = "abcd"', "S[] = T[]")
    result, program = _invoke(tmp_path, "chars.src", text)
    assert result.exit_code == 1, result.output
    assert f"{program.name}:5:1: a text of 4 characters does not fit CHAR[3]" in result.stderr


@pytest.mark.parametrize(
    ("name", "files", "where", "variable"),
    [
        ("twice.src", {"twice.src": _krl("DECL INT N\nDECL REAL N", "N = 1")}, "twice.src:3:11", "N"),
        ("one.src", {"one.src": _krl("DECL INT A, B, A", "A = 1")}, "one.src:2:16", "A"),
        (
            "d.src",
            {"d.src": "DEF d()\nA = 1\nEND\n", "d.dat": "DEFDAT d\nDECL INT A = 1\nDECL REAL A = 2\nENDDAT\n"},
            "d.dat:3:11",
            "A",
        ),
    ],
)
def test_a_name_declared_twice_is_refused(tmp_path, name, files, where, variable):
    """The second DECL replaced the first without a word."""
    for file_name, text in files.items():
        (tmp_path / file_name).write_text(text, encoding="utf-8")
    for command in ("run", "check"):
        result = CliRunner().invoke(main, [command, str(tmp_path / name)])
        assert result.exit_code == 2, result.output
        first = 2
        assert _says(result, where, f"{variable} is declared twice (first on line {first})"), result.output


def test_krl_wait_sec_negative_does_not_wait_and_says_so(tmp_path):
    text = _krl("DECL INT N", "WAIT SEC -5", "WAIT SEC 1", "$OUT[1] = TRUE")
    result, program = _invoke(tmp_path, "wait.src", text)
    assert result.exit_code == 0, result.output
    assert "$OUT[1] = on at 1.000 s" in result.output
    assert f"{program.name}:3:1: WAIT SEC -5: a negative time does not wait (taken as 0 s)" in result.output


def test_check_finds_an_over_long_rapid_string_literal(tmp_path):
    """check said clean; run stopped at the assignment."""
    result, program = _invoke(tmp_path, "s.mod", _rapid("VAR string s;", f's := "{"x" * 81}";'), "check")
    assert result.exit_code == 2, result.output
    assert _says(result, f"{program.name}:4:6", "a string of 81 characters: a string holds at most 80")
    result, _ = _invoke(tmp_path, "s.mod", _rapid("VAR string s;", f's := "{"x" * 80}";', "TPWrite s;"), "check")
    assert result.exit_code == 0, result.output


def test_check_finds_a_krl_variable_read_that_nothing_sets(tmp_path):
    """check said clean; run stopped: N has no value."""
    text = _krl("DECL INT N, M, K\nDECL FRAME F", "M = N + 1", "F.X = 1", "M = F.X", "sub(K)", "M = K")
    text += "DEF sub(X:OUT)\nDECL INT X\nX = 1\nEND\n"
    result, program = _invoke(tmp_path, "u.src", text, "check")
    assert result.exit_code == 1, result.output
    assert _says(result, f"{program.name}:4:5", "N is read but nothing in PROG sets it"), result.output
    assert result.output.count("unset-variable") == 1  # F is set by its component, K as an argument


def test_check_finds_a_data_list_variable_read_that_no_file_sets(tmp_path):
    """check said clean; run stopped: N has no value (a .dat declares it without one)."""
    (tmp_path / "u.dat").write_text("DEFDAT u PUBLIC\nDECL INT N\nDECL INT K\nDECL INT S = 3\nENDDAT\n")
    (tmp_path / "u.src").write_text("DEF u()\nDECL INT M\nM = N + S\nK = 1\nM = K\nEND\n")
    result = CliRunner().invoke(main, ["check", str(tmp_path / "u.src")])
    assert result.exit_code == 1, result.output
    assert _says(result, f"{tmp_path / 'u.src'}:3:5", "N is read but nothing in the program's files sets it")
    assert result.output.count("unset-variable") == 1  # K is set, S has its value
    run = CliRunner().invoke(main, ["run", str(tmp_path / "u.src")])
    assert "u.src:3:5: N has no value" in run.stderr


def test_a_rapid_name_declared_twice_in_a_routine_is_refused(tmp_path):
    """The second declaration replaced the first: y became a string."""
    text = _rapid("VAR num y;", "VAR string y;", "y := 1;")
    for command in ("run", "check"):
        result, program = _invoke(tmp_path, "dup.mod", text, command)
        assert result.exit_code == 2, result.output
        assert _says(result, f"{program.name}:4:1", "y declared twice in the routine (names ignore case)")
