"""Decompose/Trans grammar and interpreter."""

import numpy as np
import pytest
from dialect_base import DialectTests

from codegen.dialects.core.values import RunError
from codegen.dialects.dtrans.interpreter import load, printf
from codegen.poses import matrix_from_dtrans


def run(text: str, **inputs):
    return load(text, "t.prg").run(inputs)


A_ARRAY = "Double a[3] = {1.0, 2.0, 3.0}\n"


class TestDTrans(DialectTests):
    filename = "t.prg"
    COPIES = A_ARRAY + 'Double b[3]\nb = a\nb[0] = 5.0\nTPWrite 0, "%g", a[0]\nTPWrite 0, "%g", b[0]\n'
    BY_VALUE = A_ARRAY + 'Sub scratch(Double k[])\n  k[0] = 42.0\nEndSub\nCall scratch(a)\nTPWrite 0, "%g", a[0]\n'
    BY_REFERENCE = None
    RUNAWAY = "While True\nEndWhile\n"
    HALT = 'TPWrite 0, "stop here"\nHalt\nMovJ Trans(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)\n'
    SYNTAX_ERROR = ("Int x = 1\nIf x > 0\nEndIf\n", 2)
    UNDEFINED = ("Int x = 1\nx = y + 1\n", 2)
    OUT_OF_RANGE = ("Double a[3]\nDouble b = a[3]\n", r"index 3 out of range 0\.\.2")
    FLOAT32 = 'TPWrite 0, "%g", 16777217.0\n'
    WAIT = 'Int vis_req = 0\nWaitUntil vis_req == 1\nTPWrite 0, "go"\n'
    WAIT_NAME = "vis_req"

    def load(self, text):
        return load(text, self.filename)


def test_precedence_printf_and_functions():
    text = """Int n = 3
Function Double twice(Double v)
  Return v * 2.0
EndFunction
TPWrite 0, "%d %.2f %.1f", 1 + 2 * 3, twice(1.25) - 1.0 / 4.0, -0.04
If Not n > 5 And n == 3 Then
  TPWrite 0, "yes"
ElseIf n == 4 Then
  TPWrite 0, "four"
Else
  TPWrite 0, "no"
EndIf
"""
    assert run(text).messages == ["7 2.25 0.0", "yes"]


def test_decompose_trans_and_moves():
    text = """Point a = Trans(100.0, 20.0, 30.0, 10.0, 20.0, 30.0)
Double p[6]
Decompose p[0] = a
MovL Trans(p[0] + 1.0, p[1], p[2], p[3], p[4], p[5])
"""
    trace = run(text)
    assert np.allclose(trace.moves[0].tcp2base, matrix_from_dtrans((101, 20, 30, 10, 20, 30)), atol=1e-4)


def test_index_base_0_and_inputs():
    text = 'Double markp[3] = {0.0, 0.0, 0.0}\nTPWrite 0, "%.1f", markp[2]\n'
    assert run(text, **{"markp[2]": 7.5}).messages == ["7.5"]
    with pytest.raises(RunError, match=r"index 3 out of range 0\.\.2"):
        run("Double a[3]\nDouble b = a[3]\n")


def test_keywords_are_case_sensitive():
    with pytest.raises(RunError, match="syntax error"):
        load("if 1 == 1 Then\nEndIf\n", "t.prg")


def test_printf_checks_arguments():
    assert printf("%d:%.2f:%s", [3, 1.25, "x"], "w") == "3:1.25:x"
    with pytest.raises(RunError, match="needs more arguments"):
        printf("%d %d", [1], "w")


def test_values_are_copied_on_assignment_and_call():
    text = """Double a[3] = {1.0, 2.0, 3.0}
Double b[3]
Sub scratch(Double k[])
  k[0] = 42.0
EndSub
b = a
b[1] = 7.0
Call scratch(a)
Decompose c[0] = Trans(9.0, 8.0, 7.0, 0.0, 0.0, 0.0)
TPWrite 0, "%.0f %.0f %.0f %.0f", a[0], a[1], b[1], c[0]
"""
    program = load("Double c[6]\n" + text, "t.prg")
    assert program.run({}).messages == ["1 2 7 9"]
    assert program.run({}).messages == ["1 2 7 9"]


def test_a_store_into_a_declared_variable_keeps_its_type():
    """A value stored into a variable declared earlier (its type known only as the program runs) takes the
    variable's type: a Double into an Int is cut to a whole number, an Int into a Double a float32; the same
    type is stored as it is."""
    text = """Int n = 0
Double d = 0.0
Function Int inner()
  Int k = 0
  Double x = 0.5
  k = 2.75 + x
  x = 7
  Return k * 10 + x
EndFunction
n = 2.75
d = 3
TPWrite 0, "%g %g %d", n + 0.5, d / 2, inner()
"""
    trace = run(text)
    assert trace.messages == ["2.5 1.5 37"]
