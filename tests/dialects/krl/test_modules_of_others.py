"""KRL programs split into modules as others write them: an interrupt routine in a module of its own, and a
syntax error in a program of several modules named at its line."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from tests.dialects.krl.helpers import KRL, files

CELL = (
    "DEF CELL()\nDECL INT N\nN = 0\n"
    "GLOBAL INTERRUPT DECL 3 WHEN $IN[5] == TRUE DO ON_DOOR()\nINTERRUPT ON 3\n"
    "WAIT SEC 0.1\nINTERRUPT OFF 3\nEND\n"
)
HANDLER = "GLOBAL DEF ON_DOOR()\nDOOR_SEEN = TRUE\nEND\n"
HANDLER_DAT = "DEFDAT ON_DOOR PUBLIC\nDECL GLOBAL BOOL DOOR_SEEN=FALSE\nENDDAT\n"


def test_an_interrupt_routine_in_its_own_module_makes_one_program_with_the_module_that_declares_it():
    groups = KRL.programs(files(cell_src=CELL, on_door_src=HANDLER, on_door_dat=HANDLER_DAT))
    assert [[f.name for f in g] for g in groups] == [["cell.src", "on_door.src", "on_door.dat"]]
    # the routine is found in its module (the input never changes here: the interrupt does not fire)
    assert KRL.load_files(groups[0]).run({}, keep=("DOOR_SEEN",)).kept == {"DOOR_SEEN": False}
    assert KRL.check_files(groups[0]) == []


def test_a_syntax_error_in_a_program_of_several_modules_is_named_at_its_line():
    broken = "DEF CELL()\nDECL INT N\nN = = 0\nHELPER()\nEND\n"
    helper = "GLOBAL DEF HELPER()\nWAIT SEC 0.1\nEND\n"
    groups = KRL.programs(files(helper_src=helper, cell_src=broken))
    assert [[f.name for f in g] for g in groups] == [["cell.src", "helper.src"]]
    with pytest.raises(RunError, match=r"cell\.src:3:5: syntax error at '='"):
        KRL.load_files(groups[0])
    found = [(f.file, f.line, f.code) for f in KRL.check_files(groups[0])]
    assert found == [("cell.src", 3, "syntax")]  # HELPER is found in its module
