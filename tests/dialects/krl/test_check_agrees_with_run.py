"""check finds statically what run stops on: an array's literal subscript beyond its declared size."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError

from .helpers import KRL, files, program

DAT = "DEFDAT T\nDECL INT G[3]\nENDDAT\n"


@pytest.mark.parametrize(
    ("line", "column_of"),
    [("A[11] = 1", "A"), ("A[0] = 1", "A"), ("B[3,1] = 2.0", "B"), ("N = G[4]", "G"), ("N = A[12]", "A")],
)
def test_a_literal_index_beyond_the_declared_size_is_found_by_check_as_run_stops_on_it(line, column_of):
    decls = "DECL INT A[10]\nDECL REAL B[2,3]\nDECL CHAR S[5]\nDECL INT N"
    src = f"DEF T()\n{decls}\n{line}\nEND\n"
    with pytest.raises(RunError, match="out of range"):
        program(line, decls, "DECL INT G[3]").run({})
    found = [f for f in KRL.check_files(files(t_src=src, t_dat=DAT)) if f.code == "index"]
    assert [(f.line, f.severity) for f in found] == [(6, "error")], found
    assert f"{column_of} is declared with" in found[0].message


def test_indexes_within_the_size_and_a_routine_s_own_array_of_another_size_are_clean():
    src = (
        "DEF T()\nDECL INT A[10]\nDECL REAL B[2,3]\nA[10] = 1\nB[2,3] = 1.0\nG[3] = 1\nU()\nEND\n"
        "DEF U()\nDECL INT G[5]\nG[5] = 1\nEND\n"
    )
    assert [f for f in KRL.check_files(files(t_src=src, t_dat=DAT)) if f.code == "index"] == []


@pytest.mark.parametrize("line", ["N = 1/0", "X = 2.5/0.0"])
def test_a_division_by_a_literal_zero_is_found_by_check_as_run_stops_on_it(line):
    decls = "DECL INT N\nDECL REAL X"
    with pytest.raises(RunError, match="division by zero"):
        program(line, decls).run({})
    src = f"DEF T()\n{decls}\n{line}\nN = 4/2\nEND\n"
    found = [(f.line, f.code) for f in KRL.check_files(files(t_src=src, t_dat=DAT)) if f.severity == "error"]
    assert found == [(4, "division-by-zero")]


def _found(src: str, code: str, dat: str = DAT) -> list[tuple[int, str]]:
    return [(f.line, f.severity) for f in KRL.check_files(files(t_src=src, t_dat=dat)) if f.code == code]


@pytest.mark.parametrize(
    "lines",
    [
        "M = N\nN = 1",  # read on the line before the first that sets it
        "N = N + 1",  # the setting reads it first
        "IF M == 0 THEN\nM = N\nENDIF\nN = 2",  # a branch that reads it before
        "WHILE M < 3\nM = M + 1\nENDWHILE\nM = N\nFOR N = 1 TO 2\nENDFOR",  # a loop that does not set it
    ],
)
def test_a_variable_read_before_it_is_set_is_found_by_check_as_run_stops_on_it(lines):
    decls = "DECL INT N\nDECL INT M"
    first = lines.split("\n")
    read_line = 4 + next(i for i, line in enumerate(first) if "= N" in line or "N +" in line)
    with pytest.raises(RunError, match="N has no value"):
        program(f"M = 0\n{lines}", decls).run({})
    src = f"DEF T()\n{decls}\nM = 0\n{lines}\nEND\n"
    assert _found(src, "unset-variable") == [(read_line + 1, "warning")]


@pytest.mark.parametrize(
    "lines",
    [
        "N = 1\nM = N",
        "FOR N = 1 TO 2\nM = N\nENDFOR",
        "LOOP\nIF M > 0 THEN\nM = N\nEXIT\nENDIF\nN = 1\nM = 1\nENDLOOP",  # read in a later turn of the loop
        "REPEAT\nM = M + 1\nN = M\nUNTIL N > 2",
        "IF M == 0 THEN\nN = 1\nENDIF\nM = N",  # set in a branch before
    ],
)
def test_a_variable_set_before_it_is_read_is_clean(lines):
    decls = "DECL INT N\nDECL INT M"
    program(f"M = 0\n{lines}", decls).run({})
    src = f"DEF T()\n{decls}\nM = 0\n{lines}\nEND\n"
    assert _found(src, "unset-variable") == []


@pytest.mark.parametrize(
    ("decls", "line"),
    [
        ("DECL INT N", "N = {X 1.0}"),
        ("DECL REAL R", "R = {A 2.0}"),
        ("", "G = {X 1.0}"),  # the data list's variable
    ],
)
def test_an_aggregate_assigned_to_a_simple_type_is_found_by_check_as_run_stops_on_it(decls, line):
    with pytest.raises(RunError, match="cannot assign an aggregate"):
        program(line, decls, "DECL INT G").run({})
    src = f"DEF T()\n{decls}\n{line}\nEND\n"
    assert _found(src, "type", "DEFDAT T\nDECL INT G\nENDDAT\n") == [(3, "error")]


@pytest.mark.parametrize(("decls", "line"), [("DECL BOOL B[3]", "B[2] = {X 1.0}"), ("", "A[1] = {X 1.0}")])
def test_an_aggregate_assigned_to_an_element_of_a_simple_type_is_found_by_check(decls, line):
    """The element's type is declared as a variable's is (run stores the aggregate and stops only where it is read)."""
    src = f"DEF T()\n{decls}\n{line}\nEND\n"
    assert KRL.check_files(files(t_src=src, t_dat="DEFDAT T\nDECL INT A[3]\nENDDAT\n"))[0].code == "type"


@pytest.mark.parametrize(
    ("decls", "line"), [("DECL FRAME F", "F = {X 1.0}"), ("DECL E6POS P", "P = {X 1.0, A 2.0}"), ("", "F2 = {Y 3.0}")]
)
def test_an_aggregate_assigned_to_a_structure_is_clean(decls, line):
    program(line, decls, "DECL FRAME F2").run({})
    src = f"DEF T()\n{decls}\n{line}\nEND\n"
    assert _found(src, "type") == []


@pytest.mark.parametrize(("line", "found"), [("WAIT SEC -5", [(3, "warning")]), ("WAIT SEC -0.5", [(3, "warning")]),
                                             ("WAIT SEC 5", []), ("WAIT SEC 0", [])])  # fmt: skip
def test_a_negative_wait_is_found_by_check_as_run_warns_of_it(line, found):
    warned = [m for m in program(line).run({}).warnings if "negative time does not wait" in m]
    assert bool(warned) == bool(found)
    assert _found(f"DEF T()\n\n{line}\nEND\n", "negative-wait") == found
