"""The intercept's timing budget: its terms, the refusal at its edge, and the latencies verify applies."""

from __future__ import annotations

from pathlib import Path

import pytest
from support.programs import edited, first, verify_one

from codegen.kinds.conveyor import budget
from codegen.model.cell import CellError, load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"


def cell_with(tmp_path, **changes):
    text = CELL.read_text()
    for old, new in changes.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


def test_the_examples_budget_term_by_term():
    """At 40 mm/s, the speed over the last 24 reads (0.288 s) and predicted 0.423 s ahead (the lead: the descent of 60
    mm and the suction cup's 2 mm at 250 mm/s with its ramps 250 / 2300 s at KUKA's $ACC.CP, the grip and the planning
    time; and the count's age): its time in whole ms of $TIMER 0.059 mm; half of each spread (8 ms of the count's age
    and of the arm's start, 10 ms of the grip) 0.16, 0.16, 0.2 mm; a count 0.12 mm; the speed in whole counts 0.18 mm;
    the speed from two reads whose ages differ by up to 8 ms 0.47 mm; 10 mm/s2 of speed change 1.55 mm: 2.90 mm of the
    gripper's 3 mm, a margin of 0.10 mm; it would hold up to 43.6 mm/s. The program lands where the read that finds
    the part due predicts it: the reads' 12 ms spacing is no term."""
    cell = load_cell(CELL)
    e, horizon, window = 8.122679, 62.0 / 250.0 + 250.0 / 2300.0 + 0.05 + 0.008 + 0.008, 24 * 0.012
    speed = [horizon * 0.001 / window, 0.004, 0.004, 0.005]  # mm per mm/s
    fixed = [1 / e, horizon / (e * window)]
    ages = [horizon * 0.008 / window]
    accel = [10 * (0.5 * window + 0.012) * horizon + 5 * horizon**2]
    want = [40.0 * s for s in speed] + fixed + [40.0 * s for s in ages] + accel
    assert [t.mm(40.0) for t in budget.terms(cell, "kuka")] == pytest.approx(want, abs=1e-6)
    assert budget.total_mm(cell, "kuka") == pytest.approx(sum(want)) and 2.90 < sum(want) < 2.91
    slope = sum(speed) + sum(ages)
    assert budget.allowed_speed(cell, "kuka") == pytest.approx((3.0 - sum(fixed) - sum(accel)) / slope)
    assert 43.6 < budget.allowed_speed(cell, "kuka") < 43.7


def test_an_intercept_over_its_budget_is_refused_at_its_edge(tmp_path):
    """capture_mm just above the budget loads; just below is refused naming the largest terms and the speed the
    budget would hold at; the belt at that speed loads, a little faster is refused."""
    total = budget.total_mm(load_cell(CELL), "kuka")
    cell_with(tmp_path, **{"capture_mm = 3.0": f"capture_mm = {total + 0.01:.4f}"})
    with pytest.raises(
        CellError,
        match=r"conveyor\.pick\.capture_mm: the intercept's timing budget \(kuka\) at the "
        r"belt's 40 mm/s is 2\.90 mm, over capture_mm 2\.894\d mm; largest: the belt's speed change .*; the speed "
        r"from two reads up to 0\.008 s apart in age over 0\.288 s: 0\.47 mm; .*within it the belt may run at most "
        r"40 mm/s",
    ):
        cell_with(tmp_path, **{"capture_mm = 3.0": f"capture_mm = {total - 0.01:.4f}"})
    allowed = budget.allowed_speed(load_cell(CELL), "kuka")
    cell_with(tmp_path, **{"belt_speed_max_mm_s = 40.0": f"belt_speed_max_mm_s = {allowed - 0.1:.2f}"})
    with pytest.raises(CellError, match=r"timing budget \(kuka\) at the belt's 44\.\d+ mm/s"):
        cell_with(tmp_path, **{"belt_speed_max_mm_s = 40.0": f"belt_speed_max_mm_s = {allowed + 0.5:.2f}"})


def test_a_cell_without_an_intercept_has_no_budget(tmp_path):
    """The same belt at 200 mm/s tracked natively alone (UR) is not refused for the intercept's budget."""
    cell = cell_with(
        tmp_path,
        **{
            "belt_speed_max_mm_s = 40.0": "belt_speed_max_mm_s = 200.0",
            'tracking = { ur = "native", kuka = "intercept", abb = "native" }': 'tracking = { ur = "native" }',
            'place_clear = { ur = 2, kuka = 19, abb = "diCnvPlaceClear" }': "place_clear = { ur = 2 }",
            'zone_output = { ur = 1, kuka = 18, abb = "doCnvBeltZone" }': "zone_output = { ur = 1 }",
            "timer = { kuka = 1 }": "",
        },
    )
    assert cell.sections["conveyor"].pick.belt_speed_max_mm_s == 200.0


def test_verify_applies_the_counts_age(tmp_path):
    """A count 140-150 ms old (a slow fieldbus; the gripper's capture 5 mm keeps the budget): the program adds the
    age's middle at the speed it measured and meets the part; one that leaves the age out meets it 6.5 mm late."""
    cell = cell_with(
        tmp_path,
        **{
            "count_latency_s = [0.004, 0.012]": "count_latency_s = [0.140, 0.150]",
            "capture_mm = 3.0": "capture_mm = 5.0",
        },
    )
    program = first(cell, "kuka", "conveyor")
    row = verify_one(cell, program, scenarios=frozenset({"nominal"}))
    assert row.mismatches == 0, row.first_mismatches
    late = edited(program, lambda text: text.replace("DECL REAL CNV_LATENCY=0.145000", "DECL REAL CNV_LATENCY=0.0"))
    row = verify_one(cell, late, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("gripped" in m for m in row.first_mismatches), row.first_mismatches


def test_the_lead_holds_the_programs_planning_time(tmp_path):
    """A planning time of 140-150 ms from the last encoder read to the arm moving (motion_start_s; capture 5 mm): the
    .dat names the lead's three terms (0.356696 s descent: 62 / 250 s and its ramps 250 / 2300 s; 0.050 s hold, 0.145 s
    planning), the program meets the part; a lead without the planning time meets it about 6.5 mm late."""
    cell = cell_with(
        tmp_path,
        **{
            "motion_start_s = [0.004, 0.012]": "motion_start_s = [0.140, 0.150]",
            "capture_mm = 3.0": "capture_mm = 5.0",
        },
    )
    program = first(cell, "kuka", "conveyor")
    data = next(f.text for f in program.files if f.name.endswith(".dat"))
    assert "(0.356696: a trapezoid" in data and "(0.050000, grip_s)" in data and "(0.145000, motion_start_s" in data
    assert "DECL REAL CNV_LEAD=0.551696" in data
    row = verify_one(cell, program, scenarios=frozenset({"nominal"}))
    assert row.mismatches == 0, row.first_mismatches
    late = edited(program, lambda text: text.replace("DECL REAL CNV_LEAD=0.551696", "DECL REAL CNV_LEAD=0.406696"))
    row = verify_one(cell, late, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("gripped" in m for m in row.first_mismatches), row.first_mismatches
