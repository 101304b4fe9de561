"""A program whose load leaves out the inertia, or keeps the carried box's load after the release, or never switches
it on, fails verify for that reason on every target with loads (UR, KUKA, ABB; the dtrans dialect has no loads)."""

from __future__ import annotations

import pytest
from support.cells import example
from support.programs import edited, regex_edit, sources, verify

NUMBER = r"-?\d+\.\d+"
# the inertia of every load the program writes set to zero, in each controller's form
ZERO_INERTIA = {
    "ur": (r"(set_target_payload\([^\n]*\], )\[[^\]]*\]\)", r"\1[0, 0, 0, 0, 0, 0])"),
    "kuka": (rf"J \{{X {NUMBER},Y {NUMBER},Z {NUMBER}\}}", "J {X 0.0,Y 0.0,Z 0.0}"),
    "abb": (rf"(\[{NUMBER}, {NUMBER}, {NUMBER}, {NUMBER}\]), {NUMBER}, {NUMBER}, {NUMBER}\]", r"\1, 0, 0, 0]"),
}
# the switch back to the tool alone after each confirmed release removed: the box's load stays on
KEPT_AFTER_RELEASE = {
    "ur": (r"^\s*set_target_payload\([^\n]*# the tool alone\n", ""),
    "kuka": (r"^ {4,}\$LOAD = (?:PAL_LOAD|LOAD_DATA\[\d+\])\n", ""),
    "abb": (r"^\s*GripLoad load0;\n", ""),
}
# the switch to the tool and the box at each confirmed grip removed: the box is carried with the tool's load
NEVER_ON = {
    "ur": (r"^\s*set_target_payload\([^\n]*# the tool and the box\n", ""),
    "kuka": (r"^\s*\$LOAD = PAL_LOAD_BOX\n", ""),
    "abb": (r"^\s*GripLoad stack_box;\n", ""),
}


def first_mismatch(cell_name: str, target: str, kind: str, pattern: tuple[str, str]) -> str:
    cell = example(cell_name)
    program = sources(cell, target, kind)[0]
    mutant = edited(program, regex_edit(*pattern, 0), "mutant")
    (row,) = verify(cell, [mutant], cases=1, first_mismatch=True)
    assert row.mismatches > 0, f"verify missed the edit in the {kind} program for {target}"
    return " ".join(row.first_mismatches)


@pytest.mark.parametrize("target", sorted(ZERO_INERTIA))
def test_a_load_without_its_inertia_fails_verify(target):
    problem = first_mismatch("testmat_pallet", target, "pallet", ZERO_INERTIA[target])
    assert "has the inertia" in problem and "the plan's" in problem, problem


def test_a_belt_parts_payload_without_its_inertia_fails_verify():
    """The ABB part's own loaddata (GripLoad, tool frame) alone zeroed: the tool's stays."""
    pattern = (rf"(cnv_part := \[[^\n]*\[{NUMBER}, {NUMBER}, {NUMBER}, {NUMBER}\]), [^\]]*\]", r"\1, 0, 0, 0]")
    problem = first_mismatch("belt_pick", "abb", "conveyor", pattern)
    assert "has the inertia" in problem, problem


@pytest.mark.parametrize("target", sorted(KEPT_AFTER_RELEASE))
def test_the_boxs_load_kept_after_the_release_fails_verify(target):
    problem = first_mismatch("testmat_pallet", target, "pallet", KEPT_AFTER_RELEASE[target])
    assert "the payload in force is" in problem, problem


@pytest.mark.parametrize("target", sorted(NEVER_ON))
def test_the_boxs_load_never_switched_on_fails_verify(target):
    problem = first_mismatch("testmat_pallet", target, "pallet", NEVER_ON[target])
    assert "the payload in force is" in problem, problem
