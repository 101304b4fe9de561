"""A long `x == number` chain and a SWITCH / TEST of number CASEs run from a table: the same branch as in turn."""

from __future__ import annotations

import pytest

from codegen.dialects.krl.interpreter import load as load_krl
from codegen.dialects.rapid.interpreter import load as load_rapid
from codegen.dialects.urscript.interpreter import load as load_ur

IDS = [*range(1, 13), 7]  # twelve branches and a second `== 7`: the first one wins


def _ur(selector: str) -> list[str]:
    lines = ["def prog():", "  def pick(s):"]
    for i, n in enumerate(IDS):
        lines += [f"    {'if' if i == 0 else 'elif'} s == {n}:", f'      return "branch {i}"']
    lines += ["    else:", '      return "else"', "    end", "  end"]
    lines += [f"  textmsg(pick({selector}))", "  i = 0", "  while True:", "    i = i + 1"]
    for i, n in enumerate(IDS):
        lines += [f"    {'if' if i == 0 else 'elif'} i == {n}:", '      textmsg("loop", i)', "      break"]
    lines += ["    end", "  end", "end"]
    return load_ur("\n".join(lines) + "\n", "t.script").run({}).messages


@pytest.mark.parametrize(
    ("selector", "expected"),
    [
        ("3", "branch 2"),
        ("7", "branch 6"),
        ("3.0", "branch 2"),
        ("13", "else"),
        ('"3"', "else"),
        ("True", "branch 0"),
        ("[3]", "else"),
    ],
)
def test_a_long_elif_chain_takes_the_branch_the_comparisons_take(selector, expected):
    """Twelve `s == n` branches (a table): an int, a float equal to one, a number in none, a string and a
    list (no number equals them), True (== 1 in URScript as in the comparison), a value listed twice (the
    first branch); `return` and `break` inside the branches still leave the function and the loop."""
    messages = _ur(selector)
    assert messages[0] == expected
    assert messages[1] == "loop1"


def _krl_switch(selector: str) -> list[str]:
    cases = "".join(f"  CASE {n}\n    MSG = {i}\n" for i, n in enumerate(IDS))
    src = f"DEF t()\n  SWITCH {selector}\n{cases}  DEFAULT\n    MSG = 99\n  ENDSWITCH\nEND\n"
    dat = "DEFDAT t\n  DECL INT MSG = -1\n  DECL INT N = 2\nENDDAT\n"
    return load_krl(src, "t.src", dat).run({}, keep=("MSG",)).kept["MSG"]


@pytest.mark.parametrize(("selector", "expected"), [("3", 2), ("7", 6), ("N", 1), ("40", 99)])
def test_a_krl_switch_of_number_cases_takes_the_first_matching_case(selector, expected):
    assert _krl_switch(selector) == expected


def test_a_rapid_test_of_number_cases_takes_the_first_matching_case():
    cases = "".join(f"    CASE {n}:\n      k := {i};\n" for i, n in enumerate(IDS))
    for selector, expected in (("7", 6), ("2.5", 99), ("12", 11)):
        src = (
            "MODULE m\n  VAR num k := -1;\n  PROC main()\n"
            f"    TEST {selector}\n{cases}    DEFAULT:\n      k := 99;\n    ENDTEST\n  ENDPROC\nENDMODULE\n"
        )
        assert load_rapid(src, "t.mod").run({}, keep=("k",)).kept["k"] == expected


def test_a_chain_over_a_function_call_still_calls_it_per_branch():
    """`f() == n` in every branch: each condition calls f (a counter here) in turn, as written; no table (a
    call's source differs per branch, and the table takes a plain variable's read only)."""
    lines = ["def prog():", "  global calls = 0", "  def f():", "    global calls = calls + 1", "    return 99"]
    lines += ["  end"]
    for i, n in enumerate(IDS):
        lines += [f"  {'if' if i == 0 else 'elif'} f() == {n}:", '    textmsg("hit")']
    lines += ["  end", '  textmsg("calls", calls)', "end"]
    assert load_ur("\n".join(lines) + "\n", "t.script").run({}).messages == [f"calls{len(IDS)}"]
