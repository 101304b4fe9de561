"""The belt's third review: the intercepting arm comes down for a part only once a part left on the belt is clear of
the gripper; the grip output asserted again before any motion with a part held at the start; a grip not held released
and awaited before the lift off the part."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"

# the intercepts' wait at the clear height until the part left on the belt is past the intercept point, and none
LEFT_WAIT = {
    "kuka": ("      IF LEFT_ANY THEN\n        WHILE (CNV_Y", "      IF FALSE THEN\n        WHILE (CNV_Y"),
    "abb": ("        IF left_any THEN\n          WHILE cnv_y", "        IF FALSE THEN\n          WHILE cnv_y"),
}


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.fixture(scope="module")
def abb_intercept(tmp_path_factory):
    """The bundled cell with ABB intercepting too (a controller without the tracking option) and a slow gripper
    (145-155 ms, capture 5 mm): a longer lead, so that the arm reads the low part before its first stage's point."""
    text = CELL.read_text().replace('abb = "native" }', 'abb = "intercept" }')
    slow = (("grip_s = [0.045, 0.055]", "grip_s = [0.145, 0.155]"), ("capture_mm = 3.0 ", "capture_mm = 5.0 "))
    for old, new in slow:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path_factory.mktemp("abb") / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


def _mutant(cell, target: str, pair: tuple[str, str], label: str):
    program = first(cell, target, "conveyor")
    old, new = pair
    assert sum(f.text.count(old) for f in program.files) == 1, old
    return program, edited(program, lambda text: text.replace(old, new), label)


def _run(cell, program, category: str):
    chosen = [c for c in cases(cell) if c.category == category]
    assert len(chosen) == 1
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def test_the_tall_then_low_case_leaves_a_tall_part_where_a_low_ones_approach_would_hit_it(cell):
    """The case itself: the tall part's top above the low part's approach height (z + approach_dz), the two the least
    spacing apart, across from each other: the geometry the review found."""
    case = next(c for c in cases(cell) if c.category == "tall_then_low")
    tall, low = case.parts
    pick = cell.sections["conveyor"].pick
    assert tall.z > low.z + pick.approach_dz
    assert tall.x == low.x
    assert (low.seen_s - tall.seen_s) * case.belt.speed_mm_s == pytest.approx(max(pick.min_gap_mm, 100.0))


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_no_target_comes_down_onto_a_part_left_on_the_belt(cell, target):
    """Every target passes the case: UR and ABB come down only while they follow the part they pick; KUKA waits at
    the clear height until the tall part is clear."""
    row = _run(cell, first(cell, target, "conveyor"), "tall_then_low")
    assert row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize("target", ["kuka", "abb"])
def test_an_intercepts_descent_while_the_part_left_on_the_belt_is_under_the_gripper_fails_verify(
    cell, abb_intercept, target
):
    """Without the wait the arm comes down to the low part's approach height while the tall part, skipped as too late,
    is still under the suction cup (KUKA; ABB intercepting)."""
    chosen = abb_intercept if target == "abb" else cell
    program, mutant = _mutant(chosen, target, LEFT_WAIT[target], "no_left_wait")
    assert _run(chosen, program, "tall_then_low").mismatches == 0
    row = _run(chosen, mutant, "tall_then_low")
    assert row.mismatches == 1 and any("into part 1" in m for m in row.first_mismatches), row.first_mismatches


# the grip output asserted again before any motion with a part held at the start: (the early assert, the put-down's
# first line, the output alone); the mutant restores the assert after the way home, before the put-down
ASSERT_EARLY = {
    "ur": (
        "  if cnv_held:\n    # the grip output asserted again before any motion",
        '    textmsg("conveyor: a part held at the start',
        "    set_standard_digital_out(0, True)\n",
    ),
    "kuka": (
        "  IF HELD THEN\n    ; the grip output asserted again before any motion",
        '    CNV_MSG.MSG_TXT[] = "conveyor: a part held at the start',
        "    $OUT[17] = TRUE\n",
    ),
    "abb": (
        "    IF held THEN\n      ! the grip output asserted again before any motion",
        '      TPWrite "conveyor: a part held at the start',
        "      SetDO doGripClose, 1;\n",
    ),
}


def _late_assert(text: str, target: str) -> str:
    early, put_down, output = ASSERT_EARLY[target]
    if early not in text:
        return text
    start = text.index(early)
    end = text.index(output.strip(), start) + len(output.strip())
    end = text.index("\n", text.index("\n", end) + 1) + 1  # the block's end (endif/ENDIF) line
    text = text[:start] + text[end:]
    assert text.count(put_down) == 1
    return text.replace(put_down, output + put_down)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_grip_asserted_again_only_after_the_way_home_fails_verify(cell, target):
    """A part held at the start (the arm stopped above the belt): the grip output on again before the arm moves; a
    program that sets it only once home, before the put-down, carries the part home with the output maybe off."""
    program = first(cell, target, "conveyor")
    mutant = edited(program, lambda text: _late_assert(text, target), "late_assert")
    assert _run(cell, program, "start_mid_cycle").mismatches == 0
    row = _run(cell, mutant, "start_mid_cycle")
    assert row.mismatches == 1, row.first_mismatches
