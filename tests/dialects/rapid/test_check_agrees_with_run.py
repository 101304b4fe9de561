"""check finds statically what run stops on: an array's literal subscript beyond its declared size."""

from __future__ import annotations

import pytest

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid

HEAD = "MODULE m\n  VAR num arr{3};\n  VAR num grid{2,3};\n  VAR num x;\n  PROC main()\n    VAR num own{5};\n"
TAIL = "  ENDPROC\n  PROC p(num arr)\n    x := arr;\n  ENDPROC\nENDMODULE\n"


def _module(line: str) -> list[SourceFile]:
    return [SourceFile("m.mod", f"{HEAD}    {line}\n{TAIL}")]


@pytest.mark.parametrize(
    ("line", "named"),
    [("arr{4} := 1;", "arr"), ("x := arr{0};", "arr"), ("grid{2,4} := 1;", "grid"), ("own{6} := 1;", "own")],
)
def test_a_literal_index_beyond_the_declared_size_is_found_by_check_as_run_stops_on_it(line, named):
    with pytest.raises(RunError, match="out of range"):
        Rapid.load_files(_module(line)).run({})
    found = [f for f in Rapid.check_files(_module(line)) if f.code == "index"]
    assert [(f.line, f.severity) for f in found] == [(7, "error")], found
    assert f"{named} is declared with" in found[0].message


@pytest.mark.parametrize("line", ["arr{3} := 1;", "grid{2,3} := 1;", "own{5} := 1;", "p 1;"])
def test_indexes_within_the_size_are_clean(line):
    Rapid.load_files(_module(line)).run({})
    assert [f for f in Rapid.check_files(_module(line)) if f.code == "index"] == []


@pytest.mark.parametrize("line", ["x := 1 / 0;", "x := 5 DIV 0;", "x := 5 MOD 0.0;"])
def test_a_division_by_a_literal_zero_is_found_by_check_as_run_stops_on_it(line):
    with pytest.raises(RunError):
        Rapid.load_files(_module(line)).run({})
    found = [(f.line, f.code, f.severity) for f in Rapid.check_files(_module(line)) if f.code == "division-by-zero"]
    assert found == [(7, "division-by-zero", "error")]
    assert [f for f in Rapid.check_files(_module("x := 5 / 2;")) if f.code == "division-by-zero"] == []


def test_errraise_naming_no_errnum_is_refused_at_its_line_and_column():
    """The message read "m.mod:3:None: undefined variable E1"."""
    text = 'MODULE m\nPROC main()\n  ErrRaise "E1", 5001, "a", "b", "c", "d", "e";\nENDPROC\nENDMODULE\n'
    with pytest.raises(RunError, match=r"^m\.mod:3:12: undefined variable E1$"):
        Rapid.load_files([SourceFile("m.mod", text)])
    (found,) = Rapid.check_files([SourceFile("m.mod", text)])
    assert (found.line, found.column, found.code) == (3, 12, "undefined-name")


SEVENTY = "a" * 70
JOINED = f'  CONST string seventy := "{SEVENTY}";\n  CONST string ten := "0123456789";\n  VAR string s;\n'


def _joined(line: str) -> list[SourceFile]:
    return [SourceFile("j.mod", f"MODULE j\n{JOINED}  PROC main()\n    {line}\n  ENDPROC\nENDMODULE\n")]


@pytest.mark.parametrize(
    "line",
    [
        f's := "{SEVENTY}" + "0123456789a";',  # two literals, 81 characters
        's := seventy + ten + "a";',  # constants and a literal
        'TPWrite seventy + "a" + ten;',
        's := seventy + ten + "a" + s;',  # at least 81 whatever s holds
    ],
)
def test_a_joined_string_longer_than_80_characters_is_found_by_check_as_run_stops_on_it(line):
    with pytest.raises(RunError, match="longer than 80"):
        Rapid.load_files(_joined(line)).run({})
    found = [(f.line, f.severity) for f in Rapid.check_files(_joined(line)) if f.code == "string-too-long"]
    assert found == [(6, "error")]


@pytest.mark.parametrize(
    "line",
    [f's := "{SEVENTY}" + "0123456789";', "s := seventy + ten;", "TPWrite ten + ten + ten;", 's := "a" + s;'],
)
def test_a_joined_string_of_80_characters_or_fewer_is_clean(line):
    Rapid.load_files(_joined(line)).run({})
    assert [f for f in Rapid.check_files(_joined(line)) if f.code == "string-too-long"] == []
