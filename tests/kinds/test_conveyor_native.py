"""ABB native conveyor tracking (the Conveyor Tracking option) and UR's own encoder latched at the camera's trigger:
the programs as written, their configuration, and the changes verify must catch."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from support.programs import edited, first, run_case, verify_one

from codegen.controllers import get_target
from codegen.emit import EmitError
from codegen.kinds.conveyor import native
from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import CellError, load_cell
from codegen.render import render
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
NOMINAL = frozenset({"nominal"})


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.fixture(scope="module")
def abb(cell):
    return first(cell, "abb", "conveyor")


# (what, old, new, what the verdict says): the changes the tracking issue names
ABB_CHANGES = [
    # the pick in a fixed work object (the belt's, static) instead of the tracked one
    (
        "pick in a fixed work object",
        "MoveL down, cnv_work, fine, cnv_belt_pick_tool \\WObj:=cnv_track;",
        "MoveL down, cnv_work, fine, cnv_belt_pick_tool \\WObj:=cnv_wobj;",
        "gripped",
    ),
    # DropWObj before the lift: the lift goes to the work object's place with no object connected
    (
        "DropWObj before the lift",
        "    above.trans := [x, 0, z + CNV_Z_MAX + CNV_DZ];\n    MoveL above, cnv_work, cnv_zone",
        "    above.trans := [x, 0, z + CNV_Z_MAX + CNV_DZ];\n    DropWObj cnv_track;\n"
        "    MoveL above, cnv_work, cnv_zone",
        "",
    ),
    ("WaitWObj removed", "    WaitWObj cnv_track \\MaxTime:=CNV_CONNECT_S;\n", "", ""),
    ("the wrong mechanical unit", '[FALSE, FALSE, "CNV1",', '[FALSE, FALSE, "CNV2",', "CNV2"),
    ("another unit activated", "ActUnit CNV1;", "ActUnit CNV2;", "CNV2"),
    # the grip not on the object: the arm leaves the object (a move in another work object) before gripping
    (
        "the grip not while following",
        "    IF NOT cnv_hold() THEN",
        "    MoveL down, cnv_work, fine, cnv_belt_pick_tool \\WObj:=cnv_wobj;\n    IF NOT cnv_hold() THEN",
        "",
    ),
]


@pytest.mark.parametrize(("what", "old", "new", "says"), ABB_CHANGES)
def test_abb_native_changes_fail_verify(cell, abb, what, old, new, says):
    assert old in abb.files[0].text, what
    mutant = edited(abb, lambda text: text.replace(old, new, 1), what.replace(" ", "_"))
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=NOMINAL)
    assert row.mismatches > 0, f"verify missed: {what}"
    assert any(says in m for m in row.first_mismatches), row.first_mismatches


def test_a_part_too_close_to_the_last_is_given_up_as_the_queue_does(cell, abb):
    """The unit's queue ignores a sync within min_gap_mm of the last queued one: the program gives that part up
    (its x and z from the PLC match no object); without the check WaitWObj waits for an object that never
    comes."""
    row = verify_one(cell, abb, scenarios=NOMINAL)
    assert row.mismatches == 0, row.first_mismatches
    case = next(c for c in cases(cell) if c.category == "part_too_close")
    trace, _setup = run_case(cell, "abb", abb.load(), case, "conveyor")
    assert any(m.startswith("conveyor: too close to the part before, skipped: part 2") for m in trace.messages)
    mutant = edited(abb, lambda text: text.replace("IF cnv_queued AND Abs(", "IF FALSE AND Abs(", 1), "no_gap")
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=NOMINAL)
    assert row.mismatches > 0 and any("part_too_close" in m for m in row.first_mismatches), row.first_mismatches


def test_the_header_prints_the_configuration_the_simulated_unit_runs_on(cell, abb):
    """One source: the counts per metre, the queue tracking distance, the start window, the Sync Separation and
    the tracking range the header asks the integrator to enter are the simulated unit's."""
    text = abb.files[0].text
    unit = native.settings(cell, get_target("abb"))
    numbers = {
        "counts per metre": unit.counts_per_m,
        "queue tracking distance": unit.start_mm,
        "start window width": unit.width_mm,
        "sync separation": unit.min_gap_mm,
        "tracking range, maximum": unit.max_mm,
    }
    for name, value in numbers.items():
        found = re.search(rf"!   {re.escape(name)}\s+([\d.]+)", text)
        assert found is not None and float(found.group(1)) == pytest.approx(value, abs=0.05), name
    assert unit.counts_per_m == 8123 and unit.start_mm == pytest.approx(1200.097 - 150.0)
    assert '[FALSE, FALSE, "CNV1",' in text and "ActUnit CNV1;" in text and "DeactUnit CNV1;" in text


def test_the_ur_latches_its_own_encoder_at_the_trigger(cell):
    """Each part's count is the robot's own, latched by the thread at the trigger's rising edge (a frame late at
    most): the part's place from it is within two counts and a frame of belt travel of the truth, whatever the
    PLC's copy of the count lags by."""
    case = next(c for c in cases(cell) if c.category == "constant_speed")
    assert case.latency_s > 0.008  # the PLC's count is that old: about 0.5 mm at 60 mm/s
    row = run_cases(cell, first(cell, "ur", "conveyor"), [case], 600_000)
    assert row.mismatches == 0 and max(row.pos_errors) < 2 / 8.122679 + 40 * 0.002, row.first_mismatches


def _cell_with(tmp_path, old: str, new: str):
    text = CELL.read_text()
    assert old in text, old
    path = tmp_path / "belt_pick.toml"
    path.write_text(text.replace(old, new))
    return load_cell(path)


def test_the_cell_names_its_belts_unit_among_the_options_units(tmp_path):
    """unit = { abb = "CNV2" }: the program activates and coordinates with CNV2, the simulated controller has CNV2
    (0 mismatches); a name that is none of the facts' units is refused naming the key."""
    line = "min_gap_mm = 100.0"
    cell = _cell_with(tmp_path, line, f'{line}\nunit = {{ abb = "CNV2" }}')
    program = first(cell, "abb", "conveyor")
    text = program.files[0].text
    assert "ActUnit CNV2;" in text and '[FALSE, FALSE, "CNV2",' in text and "c2RemAllPObj" in text
    row = verify_one(cell, program, scenarios=NOMINAL)
    assert row.mismatches == 0, row.first_mismatches
    for name in ("ENDPROC", "CNV7", "cnv1"):
        with pytest.raises(
            CellError,
            match=rf"unit\.abb: expected one of 'CNV1', .*\(a conveyor's mechanical unit on abb\), got '{name}'",
        ):
            _cell_with(tmp_path, line, f'{line}\nunit = {{ abb = "{name}" }}')


def test_a_place_signal_named_as_a_word_of_rapid_is_refused_at_generate(tmp_path):
    """The place's input is written as the cell names it: a name RAPID defines (an instruction) is refused."""
    cell = _cell_with(tmp_path, 'abb = "diCnvPlaceClear"', 'abb = "WaitDI"')
    with pytest.raises(EmitError, match=r"conveyor\.pick\.place_clear\.abb: 'WaitDI' is a word or predefined name"):
        render(cell)


@pytest.mark.parametrize(
    ("old", "new", "key", "other"),
    [
        ("place_clear = { ur = 2,", "place_clear = { ur = 1,", "conveyor.pick.place_clear.ur", "cell.io.feedback.ur"),
        (
            "trigger_input = { ur = 3 }",
            "trigger_input = { ur = 2 }",
            "conveyor.pick.place_clear.ur",
            "conveyor.pick.trigger_input.ur",
        ),
        ("kuka = 19, abb =", "kuka = 18, abb =", "conveyor.pick.place_clear.kuka", "cell.io.feedback.kuka"),
    ],
)
def test_an_input_that_says_two_things_is_refused(tmp_path, old, new, key, other):
    """The place's input on the gripper's sensor or on the camera's trigger: refused naming both keys."""
    with pytest.raises(CellError, match=rf"{re.escape(key)}: input \d+ is {re.escape(other)}"):
        _cell_with(tmp_path, old, new)
