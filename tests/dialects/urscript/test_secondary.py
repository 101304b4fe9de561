"""URScript secondary programs (`sec`): run to their end; motion, sleep and threads in them refused as UR does."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load

Q = "[0, -1.57, 1.57, -1.57, -1.57, 0]"
BEHIND = r"Runtime is too much behind"


def test_a_one_line_secondary_program_runs_to_its_end():
    trace = load("sec s(): set_standard_digital_out(1, True) end\n", "s.script").run({})
    assert [(o.name, o.value) for o in trace.outputs] == [("standard_digital_out[1]", True)]
    assert trace.moves == []


def test_a_secondary_program_over_lines_computes_and_sets_outputs():
    text = "sec io():\n  n = 2\n  set_standard_digital_out(n, n == 2)\n  set_standard_digital_out(n + 1, False)\nend\n"
    trace = load(text, "io.script").run({})
    assert [(o.name, o.value) for o in trace.outputs] == [
        ("standard_digital_out[2]", True),
        ("standard_digital_out[3]", False),
    ]


def test_a_move_in_a_secondary_program_is_refused_at_its_line_with_urs_reason():
    with pytest.raises(RunError, match=rf"s\.script:3:3: movej in secondary program s: .*{BEHIND}"):
        load(f"sec s():\n  x = 1\n  movej({Q})\nend\n", "s.script")


def test_a_move_on_the_one_line_is_refused_too():
    with pytest.raises(RunError, match=rf"s\.script:1:10: movel in secondary program s: .*{BEHIND}"):
        load("sec s(): movel(p[0.3, 0, 0.2, 0, 3.14, 0]) end\n", "s.script")


def test_sleep_in_a_function_the_secondary_program_calls_is_refused_naming_it():
    text = "def wait_a_bit():\n  sleep(0.1)\nend\nsec s():\n  wait_a_bit()\nend\n"
    where = r"s\.script:2:3: sleep in secondary program s \(in wait_a_bit, which it calls\)"
    with pytest.raises(RunError, match=rf"{where}.*{BEHIND}"):
        load(text, "s.script")


def test_a_thread_started_in_a_secondary_program_is_refused():
    text = "thread t():\n  sync()\nend\nsec s():\n  h = run t()\nend\n"
    with pytest.raises(RunError, match=r"s\.script:5:7: a thread in secondary program s: threads are not supported"):
        load(text, "s.script")


def test_a_primary_program_that_defines_a_clean_secondary_still_moves():
    text = f"def prog():\n  sec light(): set_standard_digital_out(0, True) end\n  light()\n  movej({Q})\nend\n"
    trace = load(text, "p.script").run({})
    assert [(o.name, o.value) for o in trace.outputs] == [("standard_digital_out[0]", True)]
    assert len(trace.moves) == 1


def test_the_editor_outline_names_a_secondary_program_and_keeps_its_variables_inside():
    from codegen.dialects import get_dialect
    from codegen.lsp.symbols import index_of

    text = "sec s():\n  n = 2\n  set_standard_digital_out(n, True)\nend\n"
    index = index_of(get_dialect("urscript"), "s.script", text)
    assert [(s.name, s.line, s.top) for s in index.symbols] == [("s", 1, True)]
    assert [(s.name, s.top) for s in index.assigned] == [("n", False)]


def test_a_secondary_program_that_never_ends_is_stopped_with_urs_reason():
    with pytest.raises(RunError, match=rf"s\.script:1:\d+: secondary program s does not end: .*{BEHIND}"):
        load("sec s(): while True: x = 1 end end\n", "s.script").run({})
