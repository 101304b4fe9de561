"""The belt zone's output of every belt program: on while the arm is low over the belt (the PLC stops the belt on a
robot's stop then), off once it is back at the clear height; each change that restores the old program fails verify."""

from __future__ import annotations

from pathlib import Path

import pytest
from support.programs import edited, first, verify_one

from codegen.model.cell import CellError, load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
SCENARIOS = frozenset({"nominal", "gripper_silent"})

# per target: the line that sets the output on before the descent, and the one that sets it off after the lift
ON = {
    "abb": "    SetDO doCnvBeltZone, 1;\n",
    "ur": "    set_standard_digital_out(1, True)   # the arm goes down towards the part: the belt must stop with the "
    "robot\n",
    "kuka": "      $OUT[18] = TRUE ; the arm goes down towards the part: the belt must stop with the robot\n",
}
OFF_AFTER_LIFT = {
    "abb": "    MoveJ cnv_place_above, cnv_travel, fine, cnv_belt_pick_tool;\n    ! off the belt\n"
    "    SetDO doCnvBeltZone, 0;\n",
    "ur": "    set_standard_digital_out(1, False)   # the part lifted to the clear height\n",
    "kuka": "  $OUT[18] = FALSE ; off the belt\n",
}


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _mismatch(cell, target: str, old: str, new: str, what: str) -> list[str]:
    program = first(cell, target, "conveyor")
    text = program.files[0].text
    assert old in text, (target, what)
    mutant = edited(program, lambda t: t.replace(old, new), what)
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=SCENARIOS)
    assert row.mismatches > 0, f"verify missed on {target}: {what}"
    return row.first_mismatches


@pytest.mark.parametrize("target", ["abb", "ur", "kuka"])
def test_the_output_never_set_on_fails_verify(cell, target):
    found = _mismatch(cell, target, ON[target], "", "zone_never_on")
    assert any("belt zone's output" in m and "off during move" in m for m in found), found


@pytest.mark.parametrize("target", ["abb", "ur", "kuka"])
def test_the_output_set_off_before_the_lift_or_never_fails_verify(cell, target):
    """The off moved before the descent's first move (on and off at once): off during the moves low on the belt;
    the off after the lift removed: left on at the end (the output is set off at home only at the next start)."""
    found = _mismatch(
        cell,
        target,
        ON[target],
        ON[target]
        + ON[target]
        .replace("1, True", "1, False")
        .replace("doCnvBeltZone, 1", "doCnvBeltZone, 0")
        .replace("= TRUE", "= FALSE"),
        "zone_off_early",
    )
    assert any("off during move" in m for m in found), found
    found = _mismatch(
        cell,
        target,
        OFF_AFTER_LIFT[target],
        OFF_AFTER_LIFT[target].split("\n")[0] + "\n" if target == "abb" else "",
        "zone_left_on",
    )
    assert any("left on at the end" in m for m in found), found


def test_the_program_as_generated_passes_and_the_header_says_what_the_plc_does(cell):
    for target in ("abb", "ur", "kuka"):
        program = first(cell, target, "conveyor")
        assert "the PLC must stop" in program.files[0].text.replace("\n", " ").replace(";", "").replace("#", "")
        row = verify_one(cell, program, first_mismatch=True, scenarios=SCENARIOS)
        assert row.mismatches == 0, (target, row.first_mismatches)


def test_the_zone_output_is_not_the_grippers(tmp_path):
    text = CELL.read_text()
    path = tmp_path / "belt_pick.toml"
    path.write_text(
        text.replace(
            'zone_output = { ur = 1, kuka = 18, abb = "doCnvBeltZone" }',
            'zone_output = { ur = 0, kuka = 18, abb = "doCnvBeltZone" }',
        )
    )
    with pytest.raises(CellError, match=r"conveyor\.pick\.zone_output\.ur: output 0 is cell\.io\.output\.ur too"):
        load_cell(path)
