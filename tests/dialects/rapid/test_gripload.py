"""GripLoad takes persistent loaddata (its syntax: "< persistent (PERS) of loaddata >"): a CONST, a VAR or a value is
refused when the module loads, naming the line."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid

MODULE = """MODULE m
  {decl} loaddata box := [2.5, [0, 0, 50], [1, 0, 0, 0], 0, 0, 0];
  PROC main()
    GripLoad {arg};
    GripLoad load0;
  ENDPROC
ENDMODULE
"""


def load(decl: str, arg: str = "box"):
    return Rapid.load(MODULE.format(decl=decl, arg=arg), "m.mod")


def test_a_persistent_load_is_taken():
    load("PERS").run({})  # loads and runs: GripLoad box, GripLoad load0 (predefined, persistent)


@pytest.mark.parametrize("decl", ["CONST", "VAR"])
def test_a_constant_or_variable_load_is_refused(decl):
    with pytest.raises(RunError, match=rf"m\.mod:4:\d+: GripLoad takes a persistent \(PERS\) loaddata: box is {decl}"):
        load(decl)


def test_a_value_is_refused():
    with pytest.raises(RunError, match=r"m\.mod:4:\d+: GripLoad takes a persistent \(PERS\) loaddata, not a value"):
        load("PERS", "[1, [0, 0, 0], [1, 0, 0, 0], 0, 0, 0]")
