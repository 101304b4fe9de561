"""URScript grammar and interpreter."""

import math

import numpy as np
import pytest
from dialect_base import DialectTests

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load
from codegen.poses import matrix_from_ur


def prog(body: str) -> str:
    return "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"


def run(body: str, **inputs):
    return load(prog(body), "t.script").run(inputs)


class TestURScript(DialectTests):
    filename = "t.script"
    COPIES = prog('a = [1, 2, 3]\nb = a\nb[0] = 5\ntextmsg("", a[0])\ntextmsg("", b[0])')
    BY_VALUE = prog('a = [1, 2, 3]\ndef scratch(k):\n  k[0] = 42\nend\nscratch(a)\ntextmsg("", a[0])')
    BY_REFERENCE = None
    RUNAWAY = prog("while True:\n  x = 1\nend")
    HALT = prog('textmsg("stop here")\nhalt\nmovej(p[0, 0, 0, 0, 0, 0])')
    SYNTAX_ERROR = ("def prog():\n  x = 1\n  if x > 0\n  end\nend\n", 3)
    UNDEFINED = (prog("x = y + 1"), 2)
    OUT_OF_RANGE = (prog("x = [1, 2, 3]\ny = x[3]"), r"index 3 out of range 0\.\.2")
    FLOAT32 = prog('textmsg("", 16777217.0)')
    WAIT = prog('while read_input_integer_register(25) != 1:\n  sync()\nend\ntextmsg("go")')
    WAIT_NAME = "input_integer_register_25"

    def load(self, text):
        return load(text, self.filename)


def msgs(body: str, **inputs):
    return run(body, **inputs).messages


def test_precedence_and_booleans():
    assert msgs('textmsg("", 1 + 2 * 3)\ntextmsg("", -2 * 3 + 10 / 4)') == ["7", "-3.5"]
    assert msgs('textmsg("", not 1 > 2 and 3 > 2 or False)') == ["True"]
    assert msgs('textmsg("", (1 + 2) * 3)') == ["9"]


def test_control_flow_functions_and_lists():
    body = """def f(a, b):
  if a > b:
    return a
  elif a == b:
    return 0
  else:
    return b
  end
end
x = [5, 6, 7]
i = 0
s = 0
while i < 3:
  s = s + x[i]
  i = i + 1
end
textmsg("s=", s)
textmsg("f=", f(2, 9))
textmsg("g=", f(4, 4))"""
    assert msgs(body) == ["s=18", "f=9", "g=0"]


def test_pose_trans_is_matrix_composition():
    a = [0.1, -0.2, 0.3, 0.1, 0.2, -0.3]
    b = [0.4, 0.05, -0.1, 1.0, -0.5, 2.0]
    body = f"p = pose_trans(p{a}, p{b})\nmovel(p, a=1.2, v=0.25)"
    trace = run(body)
    expected = matrix_from_ur(a) @ matrix_from_ur(b)
    assert np.allclose(trace.moves[0].tcp2base, expected, atol=1e-3)
    assert trace.moves[0].kind == "linear"


def test_pose_inv_and_registers():
    body = (
        "q = pose_trans(p[0.1, 0.2, 0.3, 0, 0, 1.0], pose_inv(p[0.1, 0.2, 0.3, 0, 0, 1.0]))\nmovej(q)\n"
        "textmsg(read_input_integer_register(24), read_input_float_register(24))"
    )
    trace = run(body, input_integer_register_24=7, input_float_register_24=1.5)
    assert np.allclose(trace.moves[0].tcp2base, np.eye(4), atol=1e-4)
    assert trace.messages == ["71.5"]


def test_trig_in_radians_and_d2r():
    assert msgs('textmsg("", sin(d2r(30.0)))') == ["0.5"]
    assert float(msgs('textmsg("", r2d(atan2(1.0, 1.0)))')[0]) == pytest.approx(45.0)


def test_runtime_error_names_line():
    with pytest.raises(RunError, match=r"t.script:2:\d+: undefined variable y"):
        run("x = y + 1")
    with pytest.raises(RunError, match=r"index 3 out of range 0\.\.2"):
        run("x = [1, 2, 3]\ny = x[3]")


def test_nan_fails_comparisons():
    assert msgs('x = read_input_float_register(24)\ntextmsg("", norm(x) <= 5.0)', input_float_register_24=math.nan) == [
        "False"
    ]


def test_values_are_copied_on_assignment_and_call():
    body = """a = [1, 2, 3]
def scratch(k):
  k[0] = 42
  return k[0]
end
b = a
b[1] = 7
textmsg("", scratch(a))
textmsg("", a[0])
textmsg("", a[1])
textmsg("", b[1])"""
    program = load("def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n", "t.script")
    assert program.run({}).messages == ["42", "1", "2", "7"]
    assert program.run({}).messages == ["42", "1", "2", "7"]


def test_float32_sums():
    assert msgs('textmsg("", 0.1 + 0.2)') == ["0.3"]  # float32: 0.1f + 0.2f == 0.3f


def test_numbers_equal_in_value_keep_their_sign_and_type():
    # the compiler names each number once (codegen/dialects/core/source.py const): in one program as each alone
    lines = ["atan2(0.0, -1.0)", "atan2(-0.0, -1.0)", "-0.0", "0.0", "True", "1", "1.0", "atan2(0.0, -1.0)"]
    together = msgs("\n".join(f'textmsg("", {line})' for line in lines))
    assert together == [msgs(f'textmsg("", {line})')[0] for line in lines]
    assert together[:2] == ["3.1415927", "-3.1415927"] and together[2:6] == ["-0", "0", "True", "1"]
