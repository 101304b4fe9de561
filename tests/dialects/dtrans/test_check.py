"""codegen check of the Decompose/Trans dialect finds what run stops on, each with a program that has the fault and
one that does not."""

from __future__ import annotations

import pytest

from codegen.dialects import get_dialect
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError

DTRANS = get_dialect("dtrans")
HEAD = 'Sub Two(Int a, Int b)\n  TPWrite 0, "%d", a + b\nEndSub\nFunction Int One(Int a)\n  Return a\nEndFunction\n'
DECLS = "Int a[8]\nInt n\nDouble x\n"  # the faulty line is line 10


def _program(line: str) -> str:
    return f"{HEAD}{DECLS}{line}\n"


def _runs(text: str) -> str:
    try:
        DTRANS.load(text, "t.prg").run({})
    except RunError as exc:
        return str(exc)
    return ""


def _found(text: str) -> list[tuple[int, str, str]]:
    return [(f.line, f.severity, f.code) for f in DTRANS.check_files([SourceFile("t.prg", text)])]


@pytest.mark.parametrize(
    ("line", "code", "run_says"),
    [
        ("x = y + 1", "undefined-name", "undefined variable y"),
        ("y = 1", "undefined-name", "undeclared variable y"),
        ("Call Three(1)", "undefined-routine", "unknown routine Three"),
        ("n = Half(2)", "undefined-routine", "unknown routine Half"),
        ("Call Two(1)", "arity", "Two takes 2 arguments, got 1"),
        ("n = One(1, 2)", "arity", "One takes 1 arguments, got 2"),
        ("a[8] = 1", "index", "index 8 out of range"),
        ("n = a[-1]", "index", "index -1 out of range"),
        ("Decompose a[3] = Trans(1, 2, 3, 4, 5, 6)", "index", "Decompose needs 6 elements from index 3"),
        ("x = 2.5 / 0", "division-by-zero", "division by zero"),
        ('TPWrite 0, "%d and %d", n', "format", "needs more arguments"),
        ('TPWrite 0, "%d", n, n', "format", "fewer fields than arguments"),
        ('TPWrite 0, "%90d", n', "format", "wider than a message"),
    ],
)
def test_a_fault_run_stops_on_is_found_by_check(line, code, run_says):
    text = _program(line)
    assert run_says in _runs(text)
    assert _found(text) == [(10, "error", code)]


@pytest.mark.parametrize(
    "line",
    [
        "x = n + 1",
        "Call Two(1, 2)",
        "n = One(1) + abs(-2)",
        "a[7] = 1",
        "n = a[0]",
        "Decompose a[2] = Trans(1, 2, 3, 4, 5, 6)",
        "x = 2.5 / 2",
        'TPWrite 0, "%d and %5.2f %%", n, x',
    ],
)
def test_the_same_lines_without_the_fault_are_clean(line):
    text = _program(line)
    assert _runs(text) == ""
    assert _found(text) == []


def test_a_routine_s_own_array_and_a_parameter_are_seen_in_its_scope():
    text = (
        "Sub Fill(Int v[])\n  v[9] = 1\nEndSub\nSub Own()\n  Int a[12]\n  a[11] = 1\nEndSub\n"
        "Int a[3]\nInt w[10]\nCall Fill(w)\nCall Own()\n"
    )
    assert _runs(text) == ""
    assert _found(text) == []


def test_the_generated_programs_are_clean():
    from pathlib import Path

    root = Path(__file__).resolve().parents[3] / "generated"
    programs = sorted(root.glob("*/dtrans/*.prg"))
    assert programs
    for path in programs:
        assert _found(path.read_text(encoding="utf-8")) == [], path


def test_an_array_declared_in_a_block_hides_the_program_s_of_its_name():
    text = "Sub Own()\n  If True Then\n    Int a[12]\n    a[11] = 1\n  EndIf\nEndSub\nInt a[3]\nCall Own()\n"
    assert _runs(text) == ""
    assert _found(text) == []
