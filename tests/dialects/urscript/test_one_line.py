"""URScript with several statements on one line, as drivers send whole programs: the controller takes them."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load


def run(text: str):
    return load(text, "t.script").run({})


def test_statements_side_by_side_on_one_line_run_in_order():
    text = 'def prog():\n  x = 1  y = x + 1  textmsg("", y)  sleep(0.25)  textmsg("", x + y)\nend\n'
    trace = run(text)
    assert trace.messages == ["2", "3"]


def test_a_block_on_one_line():
    text = (
        "def prog():\n"
        '  x = 1\n  if x == 1: textmsg("one") else: textmsg("other") end\n'
        '  def twice(v): return 2 * v end\n  textmsg("", twice(21))\n'
        '  while x < 3: x = x + 1 end  textmsg("", x)\n'
        "end\n"
    )
    assert run(text).messages == ["one", "42", "3"]


def test_a_whole_program_on_one_line():
    text = 'def prog(): q = [0, -1.57, 1.57, -1.57, -1.57, 0]  movej(q)  textmsg("moved") end prog()\n'
    trace = run(text)
    assert trace.messages == ["moved"]
    assert len(trace.moves) == 1


def test_a_missing_colon_is_still_a_syntax_error_at_its_place():
    with pytest.raises(RunError, match=r"t\.script:3:13: syntax error at 'textmsg', expected one of ':'"):
        run('def prog():\n  x = 1\n  if x == 1 textmsg("one")\n  end\nend\n')
