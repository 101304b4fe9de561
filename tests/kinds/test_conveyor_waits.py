"""The pick program's waits: no part for no_part_s said once (the wait goes on), a standing belt said once with the arm
kept above it, for every target; the simulated belt's stops."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.controllers import get_target
from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.program import STANDS, lead_seconds, no_part
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
WAITS = ("belt_stands", "no_part")
TARGETS = ("ur", "kuka", "abb")


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _row(cell, source, chosen):
    return run_cases(cell, replace(source, row=0), chosen, 600_000)


def _waits(cell):
    return [c for c in cases(cell) if c.category in WAITS]


def test_the_cases_stop_the_belt_halfway_to_the_window_and_leave_the_line_without_parts(cell):
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    found = {c.category: c for c in _waits(cell)}
    stands = found["belt_stands"]
    ((start, length),) = stands.belt.stops
    assert length > pick.belt_stop_s + 1.0  # long enough to be said
    part = stands.parts[0]
    # where the part is when the belt stops: from the belt's speed alone, halfway from the camera's line to the window
    y = -conveyor.camera_offset_mm + stands.belt.speed_mm_s * (start - part.seen_s)
    assert y == pytest.approx(0.5 * (-conveyor.camera_offset_mm + pick.window_mm[0]), abs=1e-6)
    empty = found["no_part"]
    assert empty.parts == () and empty.stop_s > pick.no_part_s


@pytest.mark.parametrize("target", TARGETS)
def test_every_program_says_no_part_and_a_standing_belt_once_and_waits_above_it(cell, target):
    row = _row(cell, first(cell, target, "conveyor"), _waits(cell))
    assert row.cases == 2 and row.mismatches == 0, row.first_mismatches


# Each program with one message of its waits taken out: its case fails (the message is what verify asks of it)
SILENCED = {
    ("ur", "no_part"): ('textmsg("conveyor: no part', 'textmsg("conveyor: none'),
    ("ur", "belt_stands"): ('textmsg(str_cat("conveyor: the belt stands', 'textmsg(str_cat("conveyor: belt'),
    ("kuka", "no_part"): ('MSG_TXT[] = "conveyor: no part', 'MSG_TXT[] = "conveyor: none'),
    ("kuka", "belt_stands"): ('MSG_TXT[] = "conveyor: the belt stands', 'MSG_TXT[] = "conveyor: belt'),
    ("abb", "no_part"): ('TPWrite "conveyor: no part', 'TPWrite "conveyor: none'),
    ("abb", "belt_stands"): ('TPWrite "conveyor: the belt stands', 'TPWrite "conveyor: belt'),
}


@pytest.mark.parametrize(("target", "category"), sorted(SILENCED))
def test_a_program_that_does_not_say_so_fails_verify(cell, target, category):
    old, new = SILENCED[(target, category)]
    source = edited(first(cell, target, "conveyor"), lambda text: text.replace(old, new))
    row = _row(cell, source, [c for c in _waits(cell) if c.category == category])
    assert row.mismatches == 1
    assert "did not say so" in row.first_mismatches[0] or "said 0 times" in row.first_mismatches[0]


def test_a_program_that_says_no_part_at_every_look_fails_verify(cell):
    """Once, not at every read of the queue."""
    source = edited(
        first(cell, "kuka", "conveyor"),
        lambda text: text.replace("IF POLLS == CNV_IDLE_POLLS THEN", "IF POLLS >= CNV_IDLE_POLLS - 2 THEN"),
    )
    row = _row(cell, source, [c for c in _waits(cell) if c.category == "no_part"])
    assert row.mismatches == 1 and "'no part' said at" in row.first_mismatches[0]


STANDS_CALL = "        IF CNV_STANDS(SEQ) THEN\n"


def test_a_program_that_moves_while_the_belt_stands_fails_verify(cell):
    """KUKA's intercept: a move commanded once the belt is known to stand (here: down onto where the part would be)."""
    source = edited(
        first(cell, "kuka", "conveyor"),
        lambda text: text.replace(STANDS_CALL, "        LIN ON_PART\n" + STANDS_CALL),
    )
    row = _row(cell, source, [c for c in _waits(cell) if c.category == "belt_stands"])
    assert row.mismatches == 1 and "while the belt stood" in row.first_mismatches[0], row.first_mismatches


def _intercept_stop(cell, before_mm: float, target: str = "kuka"):
    """The belt_stands case with the belt stopping when the part is before_mm upstream of where an intercepting arm
    starts down (at the belt's speed, the lead's and the count's age's middles)."""
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    case = next(c for c in cases(cell) if c.category == "belt_stands")
    v = case.belt.speed_mm_s
    trigger = pick.intercept_mm - v * (lead_seconds(cell, get_target(target)) + pick.mean("count_latency_s"))
    at = case.parts[0].seen_s + (trigger - before_mm + conveyor.camera_offset_mm) / v
    return replace(case, category=f"belt_stands_{before_mm:g}", belt=replace(case.belt, stops=((at, 6.0),)))


@pytest.mark.parametrize(("before_mm", "picked"), [(20.0, 1), (2.0, 0)])
def test_an_intercept_stopped_near_its_descent_picks_after_the_restart_or_skips_the_part(cell, before_mm, picked):
    """The belt stops just before the intercepting arm would come down: it stays above the belt; after the restart it
    measures the speed afresh and picks the part where it is (20 mm to go), or, too close to the intercept point by
    then (2 mm to go), skips it with the too-late message."""
    case = _intercept_stop(cell, before_mm)
    row = _row(cell, first(cell, "kuka", "conveyor"), [case])
    assert row.mismatches == 0, row.first_mismatches
    assert (row.figures.picked, row.figures.skipped) == (picked, 1 - picked)


def test_without_the_fresh_measure_after_a_stand_the_intercept_misses(cell):
    """The belt stops 1 mm before the arm would come down: a program that goes on with the speed it measured while the
    belt stood (zero) comes down once a later measure catches up, too late: it meets the part off the gripper's capture
    range. With the fresh measure it skips the part as too late (the test above)."""
    fresh = "        ENDIF\n        CNV_MEASURE(SEEN, Y, V)\n"  # after the stand (and its cycle stop's check)
    source = edited(first(cell, "kuka", "conveyor"), lambda text: text.replace(fresh, "        ENDIF\n"))
    assert all(fresh not in f.text for f in source.files)
    assert _row(cell, first(cell, "kuka", "conveyor"), [_intercept_stop(cell, 1.0)]).mismatches == 0
    row = _row(cell, source, [_intercept_stop(cell, 1.0)])
    assert row.mismatches == 1 and "mm along the belt" in row.first_mismatches[0], row.first_mismatches


def test_the_messages_fit_the_controllers_lines(cell):
    assert len(no_part(cell)) <= 60 and len(STANDS) + 6 <= 80


def test_abbs_intercept_waits_out_a_standing_belt_too(tmp_path):
    """The bundled cell with ABB intercepting (no Conveyor Tracking option): its waits, and a stop just before the
    descent: 30 mm to go, picked (after the restart each stage measures the speed afresh over 0.288 s, 11.5 mm of
    travel at 40 mm/s: a stop in the first stage costs two such measures), 2 mm to go, skipped as too late."""
    text = CELL.read_text().replace('abb = "native" }', 'abb = "intercept" }')
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    cell = load_cell(path)
    chosen = [*_waits(cell), _intercept_stop(cell, 30.0, "abb"), _intercept_stop(cell, 2.0, "abb")]
    row = _row(cell, first(cell, "abb", "conveyor"), chosen)
    assert row.cases == 4 and row.mismatches == 0, row.first_mismatches
    assert (row.figures.picked, row.figures.skipped) == (2, 1)
