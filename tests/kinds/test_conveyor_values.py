"""The [conveyor] numbers a fault probe broke: a TypeError, values accepted that the pick programs cannot meet."""

from __future__ import annotations

import subprocess
import sys

import pytest
from support.cells import EXAMPLES
from support.programs import sources, verify

from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.cell import CellError, load_cell


def edited(tmp_path, *changes: tuple[str, str]):
    text = EXAMPLES["belt_pick"].read_text(encoding="utf-8")
    for old, new in changes:
        assert old in text, f"{old!r} not found"
        text = text.replace(old, new, 1)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text, encoding="utf-8")
    return path


def error_of(path) -> str:
    with pytest.raises(CellError) as info:
        load_cell(path)
    return str(info.value)


def test_an_encoder_input_given_as_a_number_exits_2_naming_the_key(tmp_path):
    """`encoder_inputs = { ur = [8, 9], kuka = 5 }`: TypeError ('int' object is not iterable) in generate,
    verify and diff. The KUKA intercepts: it reads no encoder inputs at all."""
    path = edited(tmp_path, ("encoder_inputs = { ur = [8, 9] }", "encoder_inputs = { ur = [8, 9], kuka = 5 }"))
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "generate", str(path), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "conveyor.pick.encoder_inputs.kuka: kuka does not read the encoder on its own inputs" in proc.stderr


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        (
            "encoder_inputs = { ur = [8, 9] }",
            "encoder_inputs = { ur = [8, 9], belt = [1, 2] }",
            "conveyor.pick.encoder_inputs.belt: not a tracking target: only a target tracking natively on the robot's",
        ),
        ("encoder_inputs = { ur = [8, 9] }", "encoder_inputs = { ur = [8, 8] }", "expected two different inputs"),
        ("counter_bits = 16", "counter_bits = 16.0", "conveyor.counter_bits: expected a whole number (no decimal"),
        ("counter_bits = 16", "counter_bits = 20", "conveyor.counter_bits: expected one of 16, 24, 32"),
        (
            "tool_orientation = [0.0, 0.0, 180.0]",
            "tool_orientation = [0, 0, 999999900.0]",
            "conveyor.pick.tool_orientation: angles must be within +-360 deg",
        ),
        ("origin = [799.973,", "origin = [1e9,", "conveyor.origin: a taught point: within +-10000 mm"),
        # a range narrower than the queue's 0.1 mm step holds no reading
        ("z_range_mm = [5.0, 80.0]", "z_range_mm = [0, 1e-9]", "conveyor.pick.z_range_mm: 1e-09 mm wide; at least"),
        # KUKA and ABB read x on a 16-bit group in 0.1 mm: -3276.8 .. 3276.7 mm
        ("x_range_mm = [-50.0, 150.0]", "x_range_mm = [-4000.0, 150.0]", "conveyor.pick.x_range_mm: kuka reads"),
        # two counts of this encoder are 0.246 mm
        ("window_mm = [-150.0, 100.0]", "window_mm = [-75.1, -74.9]", "min_gap_mm: must be in [0, 0.2] mm"),
    ],
)
def test_belt_numbers_the_programs_cannot_meet_are_refused(tmp_path, old, new, says):
    assert says in error_of(edited(tmp_path, (old, new)))


def test_a_window_narrower_than_two_counts_is_refused(tmp_path):
    """Two counts of this encoder are 0.246 mm: a 0.2 mm window holds no part the programs can tell inside."""
    path = edited(
        tmp_path,
        ("window_mm = [-150.0, 100.0]", "window_mm = [-75.1, -74.9]"),
        ("min_gap_mm = 100.0", "min_gap_mm = 0.0"),
    )
    assert "conveyor.pick.window_mm: 0.2 mm wide, less than two counts of the encoder (0.246 mm)" in error_of(path)


@pytest.mark.parametrize("grip", ["0.5", "2.0"])
def test_a_slow_grip_on_an_intercept_is_refused_by_the_timing_budget(tmp_path, grip):
    """grip_s 0.5 generated: verify found the part 3.6 mm off the gripper (32.5 mm at 2.0), beyond its 3 mm
    capture. The intercept's timing budget (codegen/kinds/conveyor/budget.py) holds the belt's speed change
    over the lead, which the grip lengthens."""
    says = error_of(edited(tmp_path, ("grip_s = [0.045, 0.055]", f"grip_s = {grip}")))
    assert "conveyor.pick.capture_mm: the intercept's timing budget (kuka) at the belt's 40 mm/s is" in says
    assert "the belt's speed change (10 mm/s2) over the lead" in says


def test_a_natively_tracking_target_is_not_held_to_the_intercepts_budget(tmp_path):
    path = edited(
        tmp_path,
        ('kuka = "intercept", ', ""),
        ("kuka = 19, ", ""),
        (
            'zone_output = { ur = 1, kuka = 18, abb = "doCnvBeltZone" }',
            'zone_output = { ur = 1, abb = "doCnvBeltZone" }',
        ),
        ("timer = { kuka = 1 }", ""),
        ("grip_s = [0.045, 0.055]", "grip_s = 2.0"),
    )
    assert conveyor_of(load_cell(path)).pick.grip_s == (2.0, 2.0)


def test_a_numbered_kuka_tool_verifies_in_a_belt_cell(tmp_path):
    """`[cell.tool] numbered = { kuka = 3 }` generated, then every KUKA case failed ("FRAME.X has no value")."""
    path = edited(tmp_path, ("numbered = { kuka = 2 }", "numbered = { kuka = 3 }"))  # the bundled cell's 2
    cell = load_cell(path)
    programs = sources(cell, "kuka", "conveyor")
    assert "$TOOL = TOOL_DATA[3]" in programs[0].files[0].text
    rows = verify(cell, programs, cases=1)
    assert rows[0].cases > 5 and rows[0].mismatches == 0, rows[0].first_mismatches[:2]
