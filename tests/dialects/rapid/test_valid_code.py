"""Valid RAPID that others write: placeholders, the wait instructions' display arguments, pos + aggregate."""

from __future__ import annotations

import pytest

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.dialects.rapid.interpreter import load


def mod(body: str, decls: str = "") -> str:
    return f"MODULE Cell\n{decls}\nPROC main()\n{body}\nENDPROC\nENDMODULE\n"


def findings(text: str) -> list[tuple[int, str, str]]:
    return [(f.line, f.severity, f.code) for f in Rapid.check_files([SourceFile("cell.mod", text)])]


def test_a_module_with_a_placeholder_in_a_branch_not_taken_runs_and_check_warns():
    text = mod('TPWrite "start";\nIF FALSE THEN\n  <SMT>\nENDIF\nTPWrite "end";')
    assert load(text, "cell.mod").run({}).messages == ["start", "end"]
    assert findings(text) == [(6, "warning", "placeholder")]


def test_a_placeholder_that_runs_stops_the_program_at_its_line():
    with pytest.raises(RunError, match=r"cell\.mod:5:1: <SMT> is a placeholder"):
        load(mod('TPWrite "start";\n<SMT>\nTPWrite "end";'), "cell.mod").run({})


@pytest.mark.parametrize(
    "wait",
    [
        'WaitDI diPart, 1 \\MaxTime:=2 \\Visualize \\Header:="Feeder" \\Message:="Waiting for a part" \\Icon:=iconInfo',
        'WaitDO doClamp, 0 \\Visualize \\Header:="Clamp" \\MsgArray:=lines \\Wrap \\VisualizeTime:=1',
        'WaitUntil TRUE \\MaxTime:=1 \\Visualize \\Header:="Door" \\Message:="Close the door" \\UIActiveSignal:=doUi',
    ],
)
def test_the_wait_instructions_take_their_operator_display_arguments(wait):
    decls = 'VAR string lines{2} := ["one", "two"];'
    text = mod(f'{wait};\nTPWrite "waited";', decls)
    assert load(text, "cell.mod").run({}, signals={"diPart": True}).messages == ["waited"]
    assert [f for f in findings(text) if f[1] != "warning"] == []


def test_a_pos_plus_an_aggregate_of_three_nums_is_a_pos_either_way_round():
    decls = "VAR pos p := [1, 2, 3];\nVAR pos q;"
    body = 'p := p + [10, 10, 30];\nq := [5, 5, 5] + p;\nTPWrite "p" \\Pos:=p;\nTPWrite "q" \\Pos:=q;'
    text = mod(body, decls)
    assert load(text, "cell.mod").run({}).messages == ["p[11,12,33]", "q[16,17,38]"]
    assert findings(text) == []


def test_a_pos_plus_an_aggregate_of_two_is_a_type_error_in_check():
    text = mod("p := p + [10, 10];", "VAR pos p;")
    assert findings(text) == [(4, "error", "type")]
