"""Stray and double pulses of the camera's trigger: UR's latch passes a stray count over and pairs the part with its
own; without that pairing verify's stray_pulses case fails."""

from __future__ import annotations

from pathlib import Path

from support.programs import edited, first, verify_one

from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"


def test_the_stray_pulses_case_has_a_stray_ahead_and_a_double_after_the_part():
    cell = load_cell(CELL)
    case = next(c for c in cases(cell) if c.category == "stray_pulses")
    (part,) = case.parts
    stray, double = case.pulses
    ahead = (part.seen_s - stray) * case.belt.speed_mm_s
    assert ahead >= 1.5 * cell.sections["conveyor"].pick.min_gap_mm and 0 < double - part.seen_s < 0.05


def test_a_latch_taken_without_pairing_fails_verify():
    cell = load_cell(CELL)
    program = first(cell, "ur", "conveyor")
    old = "if cnv_own_y(latched) > cnv_y(seen) + CNV_PAIR_MM:"
    assert old in program.files[0].text
    row = verify_one(cell, program, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches == 0, row.first_mismatches
    mutant = edited(program, lambda text: text.replace(old, "if False:"), "no_pairing")
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("stray_pulses" in m for m in row.first_mismatches), row.first_mismatches


def test_a_part_seen_before_the_start_skipped_by_the_unit_flush_or_fails_verify():
    """ABB native: the part the camera saw before the start had its object removed when the program emptied the
    unit's queue: skipped as queued before the start; a program that does not skip it waits for an object that is
    gone and stops out of step (a mismatch in seen_before_start)."""
    cell = load_cell(CELL)
    program = first(cell, "abb", "conveyor")
    old = "IF cnv_flushing AND cnv_unwind(cnv_flushed - seen) / CNV_COUNTS_PER_MM >= 0 THEN"
    assert old in program.files[0].text
    mutant = edited(program, lambda text: text.replace(old, "IF FALSE THEN"), "no_flush_skip")
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("seen_before_start" in m for m in row.first_mismatches), row.first_mismatches
