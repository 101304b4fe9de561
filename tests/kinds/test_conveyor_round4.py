"""The belt's fourth review: the UR program tracks by the robot's own decoder's scale (`calibrate conveyor --ticks`),
the line's cycle stop ends a wait above a standing belt, and the headers say what the integrator must set."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from support.programs import edited, first

from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
PLANT_UR = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "plant" / "belts" / "belt_ur.toml"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _mutant(cell, target: str, pairs: list[tuple[str, str]], label: str):
    program = first(cell, target, "conveyor")
    for old, _new in pairs:
        assert sum(f.text.count(old) for f in program.files) == 1, old

    def edit(text: str) -> str:
        for old, new in pairs:
            text = text.replace(old, new)
        return text

    return program, edited(program, edit, label)


def _run(cell, program, category: str):
    chosen = [c for c in cases(cell) if c.category == category]
    assert len(chosen) == 1
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def _ur_text(cell) -> str:
    return "".join(f.text for f in first(cell, "ur", "conveyor").files)


def test_the_bundled_ur_program_tracks_by_the_robots_own_scale_and_says_so(cell):
    text = _ur_text(cell)
    assert "CNV_TICKS_PER_MM = 5.092647" in text and "CNV_TICKS_PER_M = 5092.647" in text
    assert "/ CNV_TICKS_PER_MM" in text  # the latched ticks placed by the robot's scale
    assert "The scale is the robot's own decoder's: the cell's [conveyor] ticks_per_mm" in text
    plant = _ur_text(load_cell(PLANT_UR))  # a cell without ticks_per_mm: the PLC's scale, said so
    assert "The scale is the PLC counter's" in plant and "CNV_TICKS_PER_MM = -8.122679" in plant


@pytest.mark.parametrize(
    ("label", "pairs"),
    [
        # the latched ticks placed by the PLC's counts per mm, as the program did before its own scale
        ("latch by the PLC's scale", [("latched) / CNV_TICKS_PER_MM", "latched) / CNV_COUNTS_PER_MM")]),
        # tracking at the PLC's scale and sign
        (
            "tracking by the PLC's scale",
            [
                ("CNV_TICKS_PER_M = 5092.647000", "CNV_TICKS_PER_M = 8122.679000"),
                (
                    "CNV_DIR = p[-0.499994000, 0.866029000, 0.000035000",
                    "CNV_DIR = p[0.499994000, -0.866029000, -0.000035000",
                ),
            ],
        ),
    ],
)
def test_a_ur_program_on_the_plcs_scale_fails_verify(cell, label, pairs):
    """The robot's own encoder counts at 5.09 ticks/mm, up, the PLC's at -8.12 counts/mm: the program passes, and the
    program that reads its own ticks by the PLC's scale fails."""
    program, mutant = _mutant(cell, "ur", pairs, label)
    assert _run(cell, program, "constant_speed").mismatches == 0
    assert _run(cell, mutant, "constant_speed").mismatches == 1


# each target's check of the line's cycle stop in its wait above a standing belt, and the same without it
STOP_WHILE_STANDING = {
    "ur": ("if still >= CNV_STAND_POLLS and read_input_boolean_register(", "if False and read_input_boolean_register("),
    "kuka": ("IF (POLLS >= CNV_STAND_POLLS) AND $IN[", "IF FALSE AND $IN["),
    "abb": ("IF still >= CNV_STAND_POLLS AND DInput(", "IF FALSE AND DInput("),
}


@pytest.fixture(scope="module")
def abb_intercept(tmp_path_factory):
    """The bundled cell with ABB intercepting (a controller without the tracking option): its own wait routine."""
    text = CELL.read_text().replace('abb = "native" }', 'abb = "intercept" }')
    path = tmp_path_factory.mktemp("abb") / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb", "abb_intercept"])
def test_the_cycle_stop_ends_a_wait_above_a_standing_belt(cell, abb_intercept, target):
    """The belt stands for good with the part on its way and the line's cycle stop comes: every target ends its cycle
    with the arm above the belt; the same program without the check waits for the belt for ever and fails verify."""
    chosen = abb_intercept if target == "abb_intercept" else cell
    name = target.split("_")[0]
    program, mutant = _mutant(chosen, name, [STOP_WHILE_STANDING[name]], "no cycle stop in the wait")
    row = _run(chosen, program, "stop_while_standing")
    assert row.mismatches == 0, row.first_mismatches
    assert _run(chosen, mutant, "stop_while_standing").mismatches == 1


def test_an_intercept_stopped_low_goes_back_up_before_it_ends(cell):
    """KUKA's second stage: the belt stands for good 20 mm before the arm would come down onto the part, the arm at the
    part's approach height with the belt zone's output on; at the cycle stop it goes back up to the clear height and
    sets the output off before the program ends (verify's belt zone check and its given-up moves); without the check
    it waits for ever."""
    from codegen.controllers import get_target
    from codegen.kinds.conveyor.cases import STAND_EXTRA_S
    from codegen.kinds.conveyor.timing import lead_seconds

    conveyor, pick = cell.sections["conveyor"], cell.sections["conveyor"].pick
    case = next(c for c in cases(cell) if c.category == "stop_while_standing")
    v = case.belt.speed_mm_s
    trigger = pick.intercept_mm - v * (lead_seconds(cell, get_target("kuka")) + pick.mean("count_latency_s"))
    at = case.parts[0].seen_s + (trigger - 20.0 + conveyor.camera_offset_mm) / v
    low = replace(
        case,
        belt=replace(case.belt, stops=((at, case.belt.stops[0][1]),)),
        stop_s=at + pick.belt_stop_s + STAND_EXTRA_S,
    )
    program, mutant = _mutant(cell, "kuka", [STOP_WHILE_STANDING["kuka"]], "no cycle stop in the wait")
    row = run_cases(cell, replace(program, row=0), [low], 600_000, False)
    assert row.mismatches == 0, row.first_mismatches
    lifted = edited(
        program,
        lambda text: text.replace(
            "          IF STAGE == 2 THEN\n            LIN CLEAR\n", "          IF STAGE == 2 THEN\n"
        ),
        "no lift",
    )
    assert run_cases(cell, replace(lifted, row=0), [low], 600_000, False).mismatches == 1
    assert run_cases(cell, replace(mutant, row=0), [low], 600_000, False).mismatches == 1


@pytest.fixture(scope="module")
def unchecked(tmp_path_factory):
    """The bundled cell with the ABB unit's position check off (a first commissioning run)."""
    text = CELL.read_text().replace("min_gap_mm = 100.0 ", "unit_position_check = false\nmin_gap_mm = 100.0 ")
    path = tmp_path_factory.mktemp("unchecked") / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


def test_the_abb_position_check_is_on_by_default_and_said_so(cell, unchecked):
    on = "".join(f.text for f in first(cell, "abb", "conveyor").files)
    off = "".join(f.text for f in first(unchecked, "abb", "conveyor").files)
    assert "IF Abs(joints.extax.eax_a - (cnv_y(seen) - CNV_CAMERA_Y)) > CNV_SYNC_TOL THEN" in on
    assert "The position check takes the unit's joint (eax_a of CJointT)" in on and "CHECK IS OFF" not in on
    assert (
        "joints.extax" not in off and "THE POSITION CHECK IS OFF ([conveyor.pick] unit_position_check = false)" in off
    )


@pytest.mark.parametrize(
    ("category", "on", "off"), [("constant_speed", 0, 0), ("unit_missed_sync", 0, 0), ("stray_pulses", 0, 1)]
)
def test_verify_covers_the_abb_position_check_on_and_off(cell, unchecked, category, on, off):
    """With the check off the program still picks every part and stops on a sync the unit missed (no object at all);
    a stray sync pulse (an object the PLC never queued, connected first) is what only the check catches: the program
    without it follows the stray object and fails verify."""
    assert _run(cell, first(cell, "abb", "conveyor"), category).mismatches == on
    assert _run(unchecked, first(unchecked, "abb", "conveyor"), category).mismatches == off


def test_the_ur_header_asks_polyscope_to_keep_the_zone_output_at_a_stop(cell):
    """No simulation reaches PolyScope's installation: a test on the text. The program sets the zone output on before
    the arm goes down; a stop must leave it on for the PLC to hold the belt."""
    text = _ur_text(cell)
    assert "the output's action when the program stops must keep it as it is (not set it low)" in text


def test_more_pulses_pending_than_the_latch_ring_holds_stop_ur_with_their_own_message(cell):
    """A trigger chattering (40 pulses) after the second part's own while the arm works on the first: UR picks the first
    and stops as it takes the second; without the guard the second part's overwritten count reads as a scale mismatch
    (another message) and verify fails."""
    guard = "    if cnv_latches - cnv_used > CNV_RING:\n"
    program, mutant = _mutant(cell, "ur", [(guard, "    if False:\n")], "no overrun guard")
    assert _run(cell, program, "latch_overrun").mismatches == 0
    row = _run(cell, mutant, "latch_overrun")
    assert row.mismatches == 1 and "count disagree: check the trigger and the scale" in row.first_mismatches[0]


def test_a_ur_program_that_leaves_its_tcp_inactive_fails_verify(cell):
    """The socket program sets its own TCP (set_tcp with the cell's tool): without it the controller keeps the TCP it
    had, not the cell's, and verify, checking every move with the cell's tool, fails the run at its first move."""
    line = "  set_tcp(p[0.0000000, 0.0000000, 0.1500000, 0.000000000, 0.000000000, 0.000000000])\n"
    program, mutant = _mutant(cell, "ur", [(line, "")], "no set_tcp")
    assert _run(cell, program, "constant_speed").mismatches == 0
    assert _run(cell, mutant, "constant_speed").mismatches == 1


def test_the_belt_speeding_up_during_the_descent_catches_a_lead_the_other_cases_let_through(cell):
    """The belt at its fastest speed change (belt_accel_mm_s2) in the middle of the intercept's lead: every target
    picks the part; a KUKA lead 50 ms short (a descent timed without part of the grip) still passes the cases at a
    constant, a swinging and the fastest speed, and fails this one (the gripper meets the part beyond capture_mm)."""
    case = next(c for c in cases(cell) if c.category == "speeding_up")
    assert case.belt.speed_mm_s * (1 + case.belt.wobble) <= cell.sections["conveyor"].pick.belt_speed_max_mm_s + 1e-9
    for target in ("kuka", "ur", "abb"):
        assert _run(cell, first(cell, target, "conveyor"), "speeding_up").mismatches == 0, target
    short = ("DECL REAL CNV_LEAD=0.414696", "DECL REAL CNV_LEAD=0.364696")
    _program, mutant = _mutant(cell, "kuka", [short], "lead 50 ms short")
    for category in ("constant_speed", "varying_speed", "fast_belt"):
        assert _run(cell, mutant, category).mismatches == 0, category
    row = _run(cell, mutant, "speeding_up")
    assert row.mismatches == 1 and "mm along the belt" in row.first_mismatches[0], row.first_mismatches
