"""The intercept's timing as the controller moves it: the descent's ramps in the lead, the speed over measured time."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from support.programs import edited, first, run_case

from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.cell import load_cell
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _dat(program) -> str:
    return next(f.text for f in program.files if f.name.endswith(".dat"))


def _row(cell, program, categories: tuple[str, ...]):
    chosen = [c for c in cases(cell) if c.category in categories]
    return run_cases(cell, replace(program, row=0), chosen, 600_000, False)


def test_a_kuka_lin_takes_its_ramps_in_the_clock(cell):
    """The descent (a LIN of 62 mm at 0.25 m/s: approach_dz and the suction cup's 2 mm, $ACC.CP 2.3 m/s2 set by the
    program) takes 62 / 250 + 250 / 2300 s in the interpreter's clock: a trapezoid from standstill to standstill, by
    hand 0.356696 s."""
    program = first(cell, "kuka", "conveyor").load()
    case = next(c for c in cases(cell) if c.category == "constant_speed")
    trace, _setup = run_case(cell, "kuka", program, replace(case, parts=case.parts[:1]), "conveyor")
    src = next(f.text for f in first(cell, "kuka", "conveyor").files if f.name.endswith(".src")).splitlines()
    line = next(i for i, text in enumerate(src, 1) if text.strip().startswith("LIN ON_PART"))
    k, descent = next((k, m) for k, m in enumerate(trace.moves) if m.line == line)
    # KRL REALs are 32-bit: 2.3 and 0.25 as they are stored; the descent lands where the part is predicted, a fraction
    # of a mm along the belt from the point above it: its length a little over 62 mm
    before = trace.moves[k - 1]
    length = float(np.linalg.norm(descent.tcp2base[:3, 3] - before.tcp2base[:3, 3]))
    assert 62.0 - 1e-3 < length < 62.01
    assert descent.end_time - descent.start_time == pytest.approx(length / 250.0 + 0.25 / 2.3, abs=1e-6)
    assert "CNV_ACC=2.3" in _dat(first(cell, "kuka", "conveyor"))


def test_the_kuka_lead_counts_the_descents_ramps(cell):
    """The lead is the descent with its ramps (0.248 + 0.25 / 2.3 s), the grip's and the planning time's middles (0.05,
    0.008): 0.414696 s. With the lead of a descent at constant speed (0.306 s) the gripper meets the part about
    40 mm/s x 0.109 s = 4.3 mm late at the cell's top belt speed, over its 3 mm capture: verify refuses it."""
    program = first(cell, "kuka", "conveyor")
    assert "DECL REAL CNV_LEAD=0.414696" in _dat(program)
    assert _row(cell, program, ("fast_belt",)).mismatches == 0
    old = edited(program, lambda text: text.replace("CNV_LEAD=0.414696", "CNV_LEAD=0.306000"))
    row = _row(cell, old, ("fast_belt",))
    assert row.mismatches == 1 and "mm along the belt" in row.first_mismatches[0], row.first_mismatches


def _passes_as_time(text: str) -> str:
    """The KUKA program timing the belt by its loop's passes counted as exact WAIT SECs (no timer)."""
    out = text.replace("V = (Y - Y1) * 1000.0 / (T2 - T1)", "V = (Y - Y1) / 0.288")
    old = "V = (Y - CNV_YS[CNV_SLOT]) * 1000.0 / (T - CNV_TS[CNV_SLOT])"
    return out.replace(old, "V = (Y - CNV_YS[CNV_SLOT]) / (CNV_READS * CNV_POLL)")


def test_the_kuka_program_times_the_belts_speed_with_its_timer(cell):
    """Each pass of the program's loop takes 2 ms more than its WAIT SEC in verify (the pass's statements): the program
    divides the belt's travel by the time $TIMER[1] measured and meets every part; one that counts 24 passes as 24 x 12
    ms overrates the speed by a sixth and comes down early."""
    program = first(cell, "kuka", "conveyor")
    src = next(f.text for f in program.files if f.name.endswith(".src"))
    assert src.count("$TIMER[1]") >= 5 and "(T - CNV_TS[CNV_SLOT])" in src
    chosen = ("constant_speed", "fast_belt", "varying_speed")
    assert _row(cell, program, chosen).mismatches == 0
    counted = edited(program, _passes_as_time)
    assert "(CNV_READS * CNV_POLL)" in next(f.text for f in counted.files if f.name.endswith(".src"))
    row = _row(cell, counted, chosen)
    assert row.mismatches >= 1 and "mm along the belt" in row.first_mismatches[0], row.first_mismatches


def test_a_stray_trigger_pulse_does_not_make_ur_skip_the_parts_after_the_wrap(cell):
    """The camera's trigger pulses once with no part queued (a double pulse): the UR program's latched count of it is
    never claimed. Once the belt has run half the robot's count's wrap (32768 of the robot's own ticks: 6.4 m at the
    cell's ticks_per_mm) past it, it unwound to a place upstream and every later part was skipped as seen before the
    program started; passed over while the PLC presents no part once it is past the window's end, the next part 0.3 m
    of belt beyond that half wrap is picked. (Before, the
    matching loop also spun for ever on a latch upstream of the part: `while mine < 0` with mine -2; it ends there
    now, and the program without the pass-over skips the part with that message.)"""
    case = next(c for c in cases(cell) if c.category == "constant_speed")
    belt = case.belt
    half_wrap_mm = 32768.0 / abs(conveyor_of(cell).robot_ticks_per_mm)  # the robot's decoder, not the PLC's count
    later = case.parts[0].seen_s + (half_wrap_mm + 300.0) / belt.speed_mm_s
    parts = (case.parts[0], replace(case.parts[1], seen_s=later))
    stray = replace(case, category="stray_pulse", parts=parts, pulses=(case.parts[0].seen_s + 1.0,))
    program = first(cell, "ur", "conveyor")
    row = run_cases(cell, replace(program, row=0), [stray], 2_000_000, False)
    assert row.mismatches == 0 and row.figures.picked == 2, row.first_mismatches
    kept = edited(
        program, lambda text: text.replace("      sleep(CNV_POLL)\n      cnv_forget()\n", "      sleep(CNV_POLL)\n")
    )
    row = run_cases(cell, replace(kept, row=0), [stray], 2_000_000, False)
    assert row.mismatches == 1 and "seen before the program started" in row.first_mismatches[0], row.first_mismatches
