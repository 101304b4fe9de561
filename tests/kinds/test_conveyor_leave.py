"""A part given up after the arm came down for it leaves the arm at the clear height (where it waits, where the program
may end or stop), never at the part's approach height (the old behaviours fail verify); ABB's grip not confirmed
waits for the gripper to read open without a stop, and stops only once off the belt."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.program import NOT_HELD, NOT_OPENED
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases
from tests.kinds.test_conveyor_programs import intercept_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
UR_NOT_HELD = "      cnv_opened = cnv_let_go()\n      movel(cnv_on_part(x, y, {z}, CNV_DZ)"
KUKA_NOT_HELD = (
    "    OPENED = CNV_LET_GO() ; released, its feedback awaited before the lift"
    " (a part still held would be carried up)\n"
    "    LIN {pose}\n"
)
KUKA_TOO_LATE = (
    "      LIN CLEAR ; from the part's approach height back up to the clear height: the next part is awaited there\n"
)
ABB_CLEAR = "cnv_on_part(x, CNV_INTERCEPT, CNV_Z_MAX + CNV_DZ)"
ABB_BACK_UP = f"MoveL {ABB_CLEAR}, cnv_work, fine, cnv_belt_pick_tool \\WObj:=cnv_wobj;\n"
ABB_LEAVE = [
    ("cnv_leave x;", "cnv_leave x, z;"),
    ("PROC cnv_leave(num x)", "PROC cnv_leave(num x, num z)"),
    ("above.trans := [x, 0, CNV_Z_MAX + CNV_DZ];", "above.trans := [x, 0, z + CNV_DZ];"),
]
# (name, target, the edits that bring back the old text: the arm left at the part's approach height, what verify says)
LOW = [
    ("ur not held", "ur", [(UR_NOT_HELD.format(z="CNV_Z_MAX"), UR_NOT_HELD.format(z="z"))], "the lift off it"),
    ("kuka not held", "kuka", [(KUKA_NOT_HELD.format(pose="CLEAR"), KUKA_NOT_HELD.format(pose="ABOVE"))], "lift off"),
    ("kuka too late", "kuka", [(KUKA_TOO_LATE, "")], "the arm left after move"),
    ("abb native leave", "abb", ABB_LEAVE, "the lift off it"),
    (
        "abb intercept too late",
        "abb intercept",
        [("        " + ABB_BACK_UP + "        ! back at the clear height", "        ! back at the clear height")],
        "left",
    ),
    (
        "abb intercept not held",
        "abb intercept",
        [
            (
                "cnv_let_go();\n      " + ABB_BACK_UP.replace("CNV_INTERCEPT", "y"),
                "cnv_let_go();\n      MoveL above, cnv_work, fine, cnv_belt_pick_tool \\WObj:=cnv_wobj;\n",
            )
        ],
        "the lift off it",
    ),
]


def _cell_for(target: str, tmp_path):
    """The bundled cell, or with ABB intercepting (a controller without the Conveyor Tracking option)."""
    return intercept_cell(tmp_path) if target.endswith("intercept") else load_cell(CELL)


def _edit(pairs):
    def apply(text: str) -> str:
        for old, new in pairs:
            text = text.replace(old, new)
        return text

    return apply


@pytest.mark.slow  # a whole verify per mutation: the slow set
@pytest.mark.parametrize(("name", "target", "pairs", "says"), LOW, ids=[row[0] for row in LOW])
def test_an_arm_left_at_the_parts_approach_height_fails_verify(tmp_path, name, target, pairs, says):
    cell = _cell_for(target, tmp_path)
    program = first(cell, target.split()[0], "conveyor")
    for old, _new in pairs:
        assert sum(f.text.count(old) for f in program.files) >= 1, old
    good = run_cases(cell, replace(program, row=0), cases(cell), 600_000, False)
    assert good.mismatches == 0, good.first_mismatches
    row = run_cases(cell, replace(edited(program, _edit(pairs)), row=0), cases(cell), 600_000, False)
    assert row.mismatches >= 1 and all(says in m for m in row.first_mismatches), row.first_mismatches


@pytest.mark.parametrize("target", ["abb", "abb intercept"])
def test_abb_a_grip_not_confirmed_never_stops_on_the_belt(tmp_path, target):
    """ABB's path of a grip not confirmed, from the failed hold to the skip's message: the release waits for the
    gripper's feedback without a stop (cnv_let_go, no cnv_release whose timeout stops), the arm up to the clear height
    (native: cnv_leave, up in cnv_track, off the belt, DropWObj) before the stop of a gripper that did not read open.
    (The simulated gripper cannot read closed after a grip not confirmed in time, so the stop itself is not run.)"""
    cell = _cell_for(target, tmp_path)
    text = first(cell, "abb", "conveyor").files[0].text
    path = text[text.index("IF NOT cnv_hold() THEN") : text.index(NOT_HELD)]
    assert "cnv_release" not in path and "opened := cnv_let_go();" in path
    off = "cnv_leave x;" if target == "abb" else "CNV_Z_MAX + CNV_DZ), cnv_work, fine"
    assert path.index("cnv_let_go") < path.index(off) < path.index(f'IF NOT opened cnv_stop "{NOT_OPENED}";')
    if target == "abb":
        at = text.index("PROC cnv_leave(num x)")
        leave = text[at : text.index("ENDPROC", at)]
        assert "[x, 0, CNV_Z_MAX + CNV_DZ]" in leave and "DropWObj cnv_track;" in leave
    let_go = text[text.index("FUNC bool cnv_let_go()") : text.index("ENDFUNC", text.index("FUNC bool cnv_let_go()"))]
    assert "cnv_stop" not in let_go and "RETURN FALSE;" in let_go
