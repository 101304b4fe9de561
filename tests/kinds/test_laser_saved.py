"""ABB's laser TCP: asked before the write, the production tool's module saved after it (a Reset RAPID keeps it)."""

from __future__ import annotations

import pytest
from support.programs import edited, first, load_program, verify_one

from codegen.controllers import get_target
from codegen.dialects.core.values import RunError
from codegen.model.cell import load_cell

CELL = "codegen/examples/laser/laser_tcp.toml"
SAVE = '      Save "tcp_laser_tcp_tool" \\FilePath:="HOME:/tcp_laser_tcp_tool.sys";\n'
WRITE = "      tPin.tframe.trans := [lsr_tcp{1}, lsr_tcp{2}, lsr_tcp{3}];\n"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def test_the_tool_is_saved_with_its_module_right_after_the_write_and_verify_reads_the_file(cell):
    """Verify reads tPin both in the task and as the saved module's file holds it: a program without the Save leaves
    the file as the last calibration did (the TCP found is lost at a reset), and fails."""
    source = first(cell, "abb", "laser")
    text = source.files[0].text
    assert text.count(WRITE + SAVE) == 1 and text.count('    Save "') == 1
    only = frozenset({"nominal"})
    row = verify_one(cell, source, scenarios=only)
    assert row.cases >= 1 and row.mismatches == 0, row.first_mismatches
    unsaved = edited(source, lambda t: t.replace(SAVE, ""), "unsaved")
    row = verify_one(cell, unsaved, scenarios=only)
    assert row.mismatches >= 1 and "in its module's saved file" in row.first_mismatches[0], row.first_mismatches


def test_save_writes_a_modules_data_as_they_are_and_refuses_a_module_the_task_lacks():
    target = get_target("abb")
    text = """MODULE m1
  PERS num n := 1;
  PROC main()
    n := 2;
    Save "m1" \\FilePath:="HOME:/m1.mod";
    n := 3;
  ENDPROC
ENDMODULE
"""
    program = load_program(target, text, "m1.mod")
    trace = program.run({}, keep=("n", "m1:n", "m2:n"))
    assert (trace.kept["n"], trace.kept["m1:n"], trace.kept["m2:n"]) == (3, 2, None)
    with pytest.raises(RunError, match=r"Save: the task has no module m2 \(ERR_MODULE\)"):
        load_program(target, text.replace('Save "m1"', 'Save "m2"'), "m1.mod").run({})


def test_abb_asks_before_it_writes_and_a_program_that_writes_unasked_fails_verify(cell):
    """As KUKA and UR: tPin's X, Y, Z and the TCP found shown, then TPReadFK (Yes / No, \\MaxTime); the operator's No
    leaves tPin as it was; a module that takes every answer as Yes is a mismatch."""
    source = first(cell, "abb", "laser")
    text = source.files[0].text
    ask = 'TPReadFK answer, "laser: write the TCP found into tPin?", "Yes", stEmpty, stEmpty, stEmpty, "No"'
    ask += " \\MaxTime:=600.0"
    assert text.count(ask) == 1
    only = frozenset({"operator_refuses"})
    row = verify_one(cell, source, scenarios=only)
    assert (row.cases, row.mismatches) == (1, 0), row.first_mismatches
    unasked = edited(
        source, lambda t: t.replace("    IF answer <> 1 OR unanswered <> 0 THEN\n", "    IF FALSE THEN\n"), "yes"
    )
    row = verify_one(cell, unasked, scenarios=only)
    assert row.mismatches == 1, row.first_mismatches
