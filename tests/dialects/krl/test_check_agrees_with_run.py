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
