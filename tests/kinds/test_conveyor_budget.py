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
    """At 60 mm/s: a read every 12 ms 0.72 mm; half of each spread (8 ms of the count's age and of the arm's
    start, 10 ms of the grip) 0.24, 0.24, 0.3 mm; a count 0.12 mm; the speed in whole counts over 96 ms,
    predicted 0.306 s ahead (the lead and the count's age) 0.39 mm; 10 mm/s2 of speed change 0.65 mm: 2.67 mm of
    the gripper's 3 mm; it would hold up to 73 mm/s."""
    cell = load_cell(CELL)
    e, horizon = 8.122679, 60.0 / 250.0 + 0.05 + 0.008 + 0.008
    want = [0.72, 0.24, 0.24, 0.3, 1 / e, horizon / (e * 0.096), 10 * (0.048 + 0.012) * horizon + 5 * horizon**2]
    assert [t.mm(60.0) for t in budget.terms(cell)] == pytest.approx(want, abs=1e-6)
    assert budget.total_mm(cell) == pytest.approx(sum(want)) and sum(want) < 3.0
    assert budget.allowed_speed(cell) == pytest.approx((3.0 - sum(want[4:])) / 0.025)


def test_an_intercept_over_its_budget_is_refused_at_its_edge(tmp_path):
    """capture_mm just above the budget loads; just below is refused naming the largest terms and the speed the
    budget would hold at; the belt at that speed loads, a little faster is refused."""
    total = budget.total_mm(load_cell(CELL))
    cell_with(tmp_path, **{"capture_mm = 3.0": f"capture_mm = {total + 0.01:.4f}"})
    with pytest.raises(
        CellError,
        match=r"conveyor\.pick\.capture_mm: the intercept's timing budget \(kuka\) at the "
        r"belt's 60 mm/s is 2\.67 mm, over capture_mm 2\.657\d mm; largest: the encoder read every "
        r"0\.012 s: 0\.72 mm; the belt's speed change .*; within it the belt may run at most 60 mm/s",
    ):
        cell_with(tmp_path, **{"capture_mm = 3.0": f"capture_mm = {total - 0.01:.4f}"})
    allowed = budget.allowed_speed(load_cell(CELL))
    cell_with(tmp_path, **{"belt_speed_max_mm_s = 60.0": f"belt_speed_max_mm_s = {allowed - 0.1:.2f}"})
    with pytest.raises(CellError, match=r"timing budget \(kuka\) at the belt's 73\.\d+ mm/s"):
        cell_with(tmp_path, **{"belt_speed_max_mm_s = 60.0": f"belt_speed_max_mm_s = {allowed + 0.5:.2f}"})


def test_a_cell_without_an_intercept_has_no_budget(tmp_path):
    """The same belt at 200 mm/s tracked natively alone (UR) is not refused for the intercept's budget."""
    cell = cell_with(
        tmp_path,
        **{
            "belt_speed_max_mm_s = 60.0": "belt_speed_max_mm_s = 200.0",
            'tracking = { ur = "native", kuka = "intercept", abb = "native" }': 'tracking = { ur = "native" }',
            'place_clear = { ur = 2, kuka = 19, abb = "diCnvPlaceClear" }': "place_clear = { ur = 2 }",
        },
    )
    assert cell.sections["conveyor"].pick.belt_speed_max_mm_s == 200.0


def test_verify_applies_the_counts_age(tmp_path):
    """A count 90-100 ms old (a slow fieldbus; the gripper's capture 6 mm keeps the budget): the program adds the
    age's middle at the speed it measured and meets the part; one that leaves the age out meets it 5 mm late."""
    cell = cell_with(
        tmp_path,
        **{
            "count_latency_s = [0.004, 0.012]": "count_latency_s = [0.090, 0.100]",
            "capture_mm = 3.0": "capture_mm = 6.0",
        },
    )
    program = first(cell, "kuka", "conveyor")
    row = verify_one(cell, program, scenarios=frozenset({"nominal"}))
    assert row.mismatches == 0, row.first_mismatches
    late = edited(program, lambda text: text.replace("DECL REAL CNV_LATENCY=0.095000", "DECL REAL CNV_LATENCY=0.0"))
    row = verify_one(cell, late, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("gripped" in m for m in row.first_mismatches), row.first_mismatches


def test_the_lead_holds_the_programs_planning_time(tmp_path):
    """A planning time of 90-100 ms from the last encoder read to the arm moving (motion_start_s; capture 6 mm): the
    .dat names the lead's three terms (0.240 s descent, 0.050 s hold, 0.095 s planning), the program meets the part;
    a lead without the planning time meets it about 6 mm late."""
    cell = cell_with(
        tmp_path,
        **{
            "motion_start_s = [0.004, 0.012]": "motion_start_s = [0.090, 0.100]",
            "capture_mm = 3.0": "capture_mm = 6.0",
        },
    )
    program = first(cell, "kuka", "conveyor")
    data = next(f.text for f in program.files if f.name.endswith(".dat"))
    assert "(0.240000, no acceleration" in data and "(0.050000, grip_s)" in data and "(0.095000, motion_start_s" in data
    assert "DECL REAL CNV_LEAD=0.385000" in data
    row = verify_one(cell, program, scenarios=frozenset({"nominal"}))
    assert row.mismatches == 0, row.first_mismatches
    late = edited(program, lambda text: text.replace("DECL REAL CNV_LEAD=0.385000", "DECL REAL CNV_LEAD=0.290000"))
    row = verify_one(cell, late, first_mismatch=True, scenarios=frozenset({"nominal"}))
    assert row.mismatches > 0 and any("gripped" in m for m in row.first_mismatches), row.first_mismatches
