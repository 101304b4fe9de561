"""The belt's second vendor review: the release awaited before the lift from the place, the suction cup pressed onto
the part, the line's cycle stop in the wait for a part, the intercept's speed over a longer window."""

from __future__ import annotations

from dataclasses import replace
from itertools import pairwise
from pathlib import Path

import pytest
from support.programs import edited, first, verify_one

from codegen.kinds.conveyor import budget
from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import CellError, load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"

# the release at the place awaited (the gripper's feedback off) before the lift, and the output alone in its place
RELEASE_WAIT = {
    "ur": (
        "    cnv_release()\n    movel(CNV_PLACE_ABOVE,",
        "    set_standard_digital_out(0, False)\n    movel(CNV_PLACE_ABOVE,",
    ),
    "kuka": (
        "  IF NOT CNV_RELEASE() THEN\n    RETURN\n  ENDIF\n  LIN CNV_PLACE_ABOVE\n",
        "  $OUT[17] = FALSE\n  LIN CNV_PLACE_ABOVE\n",
    ),
    "abb": (
        "    cnv_release;\n    MoveL cnv_place_above,",
        "    SetDO doGripClose, 0;\n    MoveL cnv_place_above,",
    ),
}
# the suction cup pressed onto the part (overtravel_mm), and the gripper stopping at the part's top
PRESS = {
    "ur": ("  CNV_PRESS = 2.0000 ", "  CNV_PRESS = 0.0 "),
    "kuka": ("DECL REAL CNV_PRESS=2.0000 ", "DECL REAL CNV_PRESS=0.0 "),
    "abb": ("  LOCAL CONST num CNV_PRESS := 2.0000;", "  LOCAL CONST num CNV_PRESS := 0;"),
}
# the wait for the next part ends at the line's cycle stop, and a wait that does not look at it
IDLE_STOP = {
    "ur": (
        "    while read_input_integer_register(22) == last and not read_input_boolean_register(63):\n",
        "    while read_input_integer_register(22) == last:\n",
    ),
    "kuka": ("    WHILE (CNV_SEQ == LAST) AND NOT $IN[1081]\n", "    WHILE CNV_SEQ == LAST\n"),
    "abb": ("last OR DInput(diCnvStop) = 1 \\MaxTime", "last \\MaxTime"),
}


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _mutant(cell, target: str, pair: tuple[str, str], label: str):
    program = first(cell, target, "conveyor")
    old, new = pair
    assert sum(f.text.count(old) for f in program.files) >= 1, old
    return program, edited(program, lambda text: text.replace(old, new), label)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_lift_from_the_place_before_the_gripper_let_go_fails_verify(cell, target):
    """The gripper lets go grip_s after its output (45-55 ms, as a vacuum gripper does): every program waits for its
    feedback to drop before it lifts from the place; one that lifts on the output alone carries the part off."""
    program, mutant = _mutant(cell, target, RELEASE_WAIT[target], "no_release_wait")
    row = verify_one(cell, program, first_mismatch=True, scenarios=frozenset({"nominal"}), clearance=False)
    assert row.mismatches == 0, row.first_mismatches
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}), clearance=False)
    assert row.mismatches > 0 and any("let go" in m for m in row.first_mismatches), row.first_mismatches


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_grip_at_the_parts_top_without_the_suction_cups_overtravel_fails_verify(cell, target):
    """overtravel_mm (2 mm on the bundled cell): the gripper comes down that far past the part's top; a program that
    stops at the top grips 2 mm high."""
    _program, mutant = _mutant(cell, target, PRESS[target], "no_overtravel")
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}), clearance=False)
    assert row.mismatches > 0 and any("in height" in m for m in row.first_mismatches), row.first_mismatches


def _cell_with(tmp_path, *pairs: tuple[str, str]):
    text = CELL.read_text()
    for old, new in pairs:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


@pytest.mark.parametrize("value", ["-1.0", "25.0"])
def test_an_overtravel_out_of_its_bounds_is_refused(tmp_path, value):
    """overtravel_mm within 0..20 mm: the message names the key."""
    with pytest.raises(CellError, match=r"conveyor\.pick\.overtravel_mm"):
        _cell_with(tmp_path, ("overtravel_mm = 2.0 ", f"overtravel_mm = {value} "))


def test_an_overtravel_as_deep_as_the_approach_is_refused(tmp_path):
    """The gripper's approach height above the part must be more than the overtravel below its top."""
    pairs = (("approach_dz = 60.0\n", "approach_dz = 15.0\n"), ("overtravel_mm = 2.0 ", "overtravel_mm = 15.0 "))
    with pytest.raises(CellError, match=r"conveyor\.pick\.overtravel_mm: must be less than approach_dz \(15 mm\)"):
        _cell_with(tmp_path, *pairs)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_wait_for_the_next_part_blind_to_the_lines_stop_fails_verify(cell, target):
    """The line's cycle stop ends the wait for the next part on every target (no part comes for no_part_s + 10 s,
    then the stop): a wait that does not look at it never ends."""
    program, mutant = _mutant(cell, target, IDLE_STOP[target], "no_stop")
    chosen = [c for c in cases(cell) if c.category == "no_part"]
    assert run_cases(cell, replace(program, row=0), chosen, 600_000, False).mismatches == 0
    row = run_cases(cell, replace(mutant, row=0), chosen, 600_000, False)
    assert row.mismatches == 1, row.first_mismatches


def _wide_cycle(tmp_path):
    """The bundled cell with a PLC whose count is 4-36 ms old (a 32 ms cycle), the gripper's capture 5 mm (its budget
    4.9 mm at 40 mm/s)."""
    text = CELL.read_text()
    for old, new in (
        ("count_latency_s = [0.004, 0.012]", "count_latency_s = [0.004, 0.036]"),
        ("capture_mm = 3.0 ", "capture_mm = 5.0 "),
    ):
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


def _eight_reads(text: str) -> str:
    """The speed over the last 8 reads (96 ms), as before the longer window."""
    text = text.replace("DECL INT CNV_READS=24 ", "DECL INT CNV_READS=8 ").replace("[24]", "[8]")
    return text.replace("WAIT SEC 0.288\n", "WAIT SEC 0.096\n")


def test_the_intercepts_longer_window_meets_the_part_closer_on_a_slow_plc(tmp_path):
    """The count's age runs through 4-36 ms as the PLC copies the counter once a 32 ms cycle: two reads of the speed
    differ in age by up to 32 ms. Over 24 reads (0.288 s) the budget counts 1.93 mm for it at 40 mm/s (over 96 ms it
    would be 5.8 mm); in verify the program meets every part within 3 mm, while the same program measuring over 8 reads
    is off by more (measured: 2.83 against 3.28 mm on the four-part cases). Both stay within this cell's 5 mm: a
    measurement, not a verify failure (the budget refuses the cell at a capture the 8 reads would miss)."""
    cell = _wide_cycle(tmp_path)
    term = next(t for t in budget.terms(cell, "kuka") if "two reads" in t.what)
    assert term.mm(40.0) == pytest.approx(40.0 * (0.414696 + 0.020) * 0.032 / 0.288, abs=1e-4)
    program = first(cell, "kuka", "conveyor")
    short = edited(program, _eight_reads, "eight_reads")
    assert all("CNV_READS=24" not in f.text and "WAIT SEC 0.288" not in f.text for f in short.files)
    chosen = [c for c in cases(cell) if len(c.parts) == 4]
    assert chosen
    good = run_cases(cell, replace(program, row=0), chosen, 600_000, False)
    old = run_cases(cell, replace(short, row=0), chosen, 600_000, False)
    assert good.mismatches == 0 and old.mismatches == 0, (good.first_mismatches, old.first_mismatches)
    worst = (max(good.pos_errors), max(old.pos_errors))
    assert worst[0] < 3.0 and worst[1] > worst[0] + 0.25, worst


def test_the_intercept_lands_where_its_last_read_predicts_the_part(cell):
    """On the text (no simulation tells a landing a pass early from one on time within the capture range): the
    descent's end along the belt is the read's place, its age and the lead at the measured speed, on KUKA and ABB."""
    kuka = next(f.text for f in first(cell, "kuka", "conveyor").files if f.name.endswith(".src"))
    assert "  BOX.Y = Y + V * (CNV_LATENCY + CNV_LEAD)\n  BOX.Z = PART_Z - CNV_PRESS" in kuka
    assert kuka.index("BOX.Y = Y + V * (CNV_LATENCY + CNV_LEAD)") < kuka.index("  LIN ON_PART")


MISMATCH_STOP = (
    "      cnv_stop(\"conveyor: the robot's encoder and the PLC's count disagree: check the trigger and the scale\")\n"
)
# the part without a latch of its own, seen after the start, told apart from one seen before it; and read as one
AS_EARLY = (
    "      # missed, or its encoder and the PLC's counter disagree (a stop: every later part would meet the same)\n"
    + MISMATCH_STOP,
    '      textmsg(str_cat("conveyor: seen before the program started, skipped: part ", to_str(seq)))\n'
    "      continue\n",
)
# the robot's own count against the PLC's once the part is at the window, and no such comparison
NO_WINDOW_CHECK = ("    if norm(cnv_own_y(mine) - cnv_y(seen)) > CNV_PAIR_MM:\n", "    if False:\n")


@pytest.mark.parametrize(
    ("category", "pair"), [("trigger_missed", AS_EARLY), ("latch_scale", NO_WINDOW_CHECK)], ids=["missed", "scale"]
)
def test_a_latch_and_plc_mismatch_is_said_as_such_on_ur(cell, category, pair):
    """UR: a trigger pulse the robot's input missed (the part seen after the start, no latch of its own) and a robot's
    decoder counting half the PLC's counts (the belt calibrated with the PLC's) each stop the program with the
    mismatch's message before a grip; read as a part seen before the start, or not compared at the window, they
    pass."""
    program, mutant = _mutant(cell, "ur", pair, f"no_{category}")
    chosen = [c for c in cases(cell) if c.category == category]
    assert len(chosen) == 1
    assert run_cases(cell, replace(program, row=0), chosen, 2_000_000, False).mismatches == 0
    row = run_cases(cell, replace(mutant, row=0), chosen, 2_000_000, False)
    assert row.mismatches == 1, row.first_mismatches


def test_the_counters_wrap_with_parts_queued(cell):
    """Four parts 2 s apart on the belt whose 16-bit counter wraps about 9.7 s in: the later ones seen before the wrap
    and taken after it, while the arm works on the first. Every target picks or skips each for a reason verify takes
    (measured: UR 1 picked and 3 skipped past the window's end, KUKA 1 and 3, ABB 2 and 2); KUKA without unwinding the
    count's difference never finds the part in the window."""
    chosen = [c for c in cases(cell) if c.category == "rollover_queued"]
    belt = chosen[0].belt
    seen = [belt.count(p.seen_s) for p in chosen[0].parts]
    assert all(a > b for a, b in pairwise(seen)) and belt.count(12.0) > seen[0]  # wrapped by 12 s
    for target in ("ur", "kuka", "abb"):
        row = run_cases(cell, replace(first(cell, target, "conveyor"), row=0), chosen, 2_000_000, False)
        assert row.mismatches == 0 and row.figures.picked >= 1, (target, row.first_mismatches)
    pair = ("CNV_UNWIND(CNV_ENC - SEEN)", "(CNV_ENC - SEEN)")
    _program, mutant = _mutant(cell, "kuka", pair, "no_unwind")
    assert run_cases(cell, replace(mutant, row=0), chosen, 2_000_000, False).mismatches == 1


@pytest.mark.parametrize(
    ("target", "pair"),
    [("kuka", ("CNV_LEAD=0.514696", "CNV_LEAD=0.364696")), ("abb", ("CNV_LEAD := 0.406000", "CNV_LEAD := 0.256000"))],
)
def test_a_lead_without_a_slow_grippers_hold_fails_verify(tmp_path, target, pair):
    """A gripper that holds 145-155 ms after its output (capture 5 mm): each intercept's lead counts its 0.15 s; a lead
    without it meets the part 6 mm late at 40 mm/s (the bundled gripper's 0.05 s, 2 mm, stays within its capture)."""
    text = CELL.read_text().replace('abb = "native" }', 'abb = "intercept" }')
    for old, new in (
        ("grip_s = [0.045, 0.055]", "grip_s = [0.145, 0.155]"),
        ("capture_mm = 3.0 ", "capture_mm = 5.0 "),
    ):
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    cell = load_cell(path)
    program, mutant = _mutant(cell, target, pair, "no_grip_in_lead")
    row = verify_one(cell, program, first_mismatch=True, scenarios=frozenset({"nominal"}), clearance=False)
    assert row.mismatches == 0, row.first_mismatches
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset({"nominal"}), clearance=False)
    assert row.mismatches > 0 and any("gripped" in m for m in row.first_mismatches), row.first_mismatches
