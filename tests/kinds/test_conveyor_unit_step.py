"""ABB native belt program as a second review reads it: the unit's logical axis in every target, WaitWObj with
\\MaxTime and its errors by name, the unit's queue checked against the PLC's, the wait after DropWObj, the grip
output asserted again on a part held at the start; each change that restores the old program fails verify (or, where
no simulation reaches it, a test on the text)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from support.programs import edited, first, run_case, verify_one

from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.program import OUT_OF_STEP
from codegen.model.cell import CellError, load_cell
from codegen.sim.belt import Belt, Part, TrackingUnit, UnitSettings

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"


@pytest.fixture(scope="module")
def belt():
    """The bundled belt cell and its ABB native program."""
    loaded = load_cell(CELL)
    return loaded, first(loaded, "abb", "conveyor")


@pytest.fixture(scope="module")
def cell(belt):
    return belt[0]


def _fails(cell, program, what: str, old: str, new: str, scenarios, says: str = "") -> None:
    text = program.files[0].text
    assert old in text, what
    mutant = edited(program, lambda t: t.replace(old, new), what.replace(" ", "_"))
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=frozenset(scenarios))
    assert row.mismatches > 0, f"verify missed: {what}"
    assert any(says in m for m in row.first_mismatches), row.first_mismatches


def test_every_target_gives_the_units_axis_a_value(belt):
    """Used after ActUnit CNV1, every robtarget and jointtarget has 0 in the unit's slot (eax_a by the facts' default),
    never 9E+09; the position read before ActUnit gets it too. The program as generated: 0 mismatches."""
    cell, abb = belt
    text = abb.files[0].text
    targets = re.findall(r"CONST (?:robtarget|jointtarget) \w+ := .*?;", text, re.S)
    assert len(targets) == 4
    for declared in targets:
        assert re.search(r"\[0, 9E\+09, 9E\+09, 9E\+09, 9E\+09, 9E\+09\]\];$", declared), declared
    assert re.search(r"ActUnit CNV1;\n(?:\s*!.*\n)*\s*now\.extax\.eax_a := 0;", text)
    row = verify_one(cell, abb, first_mismatch=True)
    assert row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize(
    ("what", "old", "new", "scenarios", "says"),
    [
        (
            "9E+09 in the unit's slot",
            "[0, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]",
            "[9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]",
            {"nominal"},
            "logical axis 7 of the active unit CNV1",
        ),
        ("the position read before ActUnit kept", "    now.extax.eax_a := 0;\n", "", {"start_away"}, "eax_a"),
    ],
)
def test_an_unused_axis_of_an_active_unit_fails_verify(belt, what, old, new, scenarios, says):
    cell, abb = belt
    _fails(cell, abb, what, old, new, scenarios, says)


def test_the_units_axis_is_the_cells(tmp_path):
    """unit_axis = { abb = 12 }: the slot is eax_f in every target and in the check; a slot outside 7..12 is refused
    naming the key."""
    text = CELL.read_text()
    line = "min_gap_mm = 100.0"
    path = tmp_path / "belt_pick.toml"
    path.write_text(text.replace(line, f"{line}\nunit_axis = {{ abb = 12 }}"))
    cell = load_cell(path)
    program = first(cell, "abb", "conveyor")
    body = program.files[0].text
    assert "[9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 0]]" in body and "joints.extax.eax_f" in body
    assert "[0, 9E+09" not in body
    row = verify_one(cell, program, scenarios=frozenset({"nominal", "start_away"}))
    assert row.mismatches == 0, row.first_mismatches
    path.write_text(text.replace(line, f"{line}\nunit_axis = {{ abb = 6 }}"))
    with pytest.raises(CellError, match=r"conveyor\.pick\.unit_axis\.abb"):
        load_cell(path)


def test_the_out_of_step_queues_stop_the_program_with_its_message(belt):
    """A sync the unit missed: no object for the part once the PLC's count has it in the window (WaitWObj \\MaxTime
    and ERR_WAIT_MAXTIME); a stray sync ahead of the part: WaitWObj connects the stray object, whose position is not
    the part's. Both stop with the message, the object dropped, before any grip."""
    cell, abb = belt
    for category in ("unit_missed_sync", "stray_pulses"):
        case = next(c for c in cases(cell) if c.category == category)
        trace, setup = run_case(cell, "abb", abb.load(), case, "conveyor")
        unit = setup.devices[0].unit
        assert trace.halted and OUT_OF_STEP in (trace.halt_message or "") + " ".join(trace.messages), category
        assert unit.connected is None, category
        assert not any(o.value for o in trace.outputs if o.name == "doGripClose"), category


@pytest.mark.parametrize(
    ("what", "old", "new"),
    [
        # without \MaxTime the wait for an object the unit never queued does not end
        ("WaitWObj without MaxTime", "WaitWObj cnv_track \\MaxTime:=CNV_CONNECT_S;", "WaitWObj cnv_track;"),
        # every error of WaitWObj read as the part lost (the old handler): the missed sync reads as a lost part
        (
            "any error as lost",
            "    IF ERRNO = ERR_CNV_DROPPED RETURN 1;\n    IF ERRNO = ERR_WAIT_MAXTIME RETURN 2;\n    RAISE;",
            "    RETURN 1;",
        ),
        # the connected object taken as the part whatever its position
        (
            "no position check",
            "IF Abs(joints.extax.eax_a - (cnv_y(seen) - CNV_CAMERA_Y)) > CNV_SYNC_TOL THEN",
            "IF FALSE THEN",
        ),
    ],
)
def test_the_queue_checks_removed_fail_verify(belt, what, old, new):
    cell, abb = belt
    _fails(cell, abb, what, old, new, {"nominal"})


def test_the_grip_output_asserted_again_on_a_part_held_at_the_start(cell):
    """Every target sets the grip output again before any motion with a part held at the start; without it verify
    fails the start_mid_cycle case."""
    edits = {
        "abb": ("      SetDO doGripClose, 1;\n    ENDIF\n", "    ENDIF\n"),
        "ur": ("    set_standard_digital_out(0, True)\n  end\n  set_tcp", "  end\n  set_tcp"),
        "kuka": ("    $OUT[17] = TRUE\n  ENDIF\n  $TOOL", "  ENDIF\n  $TOOL"),
    }
    for target, (old, new) in edits.items():
        program = first(cell, target, "conveyor")
        _fails(cell, program, f"{target} no grip again", old, new, {"start_mid_cycle"}, "start_mid_cycle")


def test_the_wait_after_each_dropwobj_and_the_errors_by_name_on_the_text(belt):
    """No simulated controller reaches these (the option's reason for the wait is not stated in what was readable;
    ERR_CNV_NOT_ACT and ERR_CNV_CONNECT need a program that is wrong elsewhere): every DropWObj is followed by the
    wait before the next WaitWObj, and WaitWObj's handler names its two errors and raises any other."""
    abb = belt[1]
    text = abb.files[0].text
    drops = re.findall(r"DropWObj cnv_track;\n(\s*)(\S[^\n]*)", text)
    assert len(drops) == 4  # at the start, the lift, leaving a part, and before the stop out of step
    for _indent, following in drops:
        assert following in ("WaitTime CNV_DROP_SETTLE;", 'cnv_stop "' + OUT_OF_STEP + '";'), following
    assert "CNV_DROP_SETTLE := 0.200;" in text
    handler = re.search(r"LOCAL FUNC num cnv_connect\(\).*?ENDFUNC", text, re.S).group(0)
    assert "\\MaxTime:=CNV_CONNECT_S" in handler and handler.rstrip().endswith("RAISE;\n  ENDFUNC")
    assert "ERRNO = ERR_CNV_DROPPED" in handler and "ERRNO = ERR_WAIT_MAXTIME" in handler


def test_the_header_names_the_units_parameters_as_the_option_does(belt):
    abb = belt[1]
    text = abb.files[0].text
    assert "!   sync separation              100.0 mm" in text and "minimum distance" not in text
    assert "!   logical axis                 7" in text


def _unit(**changes) -> TrackingUnit:
    settings = UnitSettings("CNV1", 10_000, __import__("numpy").eye(4), 100.0, 100.0, 30.0, 500.0)
    belt = Belt(50.0, 10.0)
    parts = [Part(1, 1.0, 0.0, 0.0), Part(2, 5.0, 0.0, 0.0)]
    return TrackingUnit(settings, belt, parts, **changes)


def test_the_simulated_units_own_sync_input():
    """A stray sync is an object of its own (the oldest); a missed sync leaves the part out of the queue, and it is
    not counted as ignored for being too close."""
    unit = _unit(extra_syncs=(0.2,), missed=frozenset({2}))
    seqs = [p.seq for p, _count in unit.queued()]
    assert seqs == [-1, 1] and unit.ignored() == set()
    seq, due, connected = unit.connect(0.0)
    assert seq == -1 and connected and due == pytest.approx(0.2 + 2.0, abs=1e-3)


def test_waitwobj_maxtime_leaves_the_queue_as_it_was():
    """connect(until): none connected by then is (None, until, None), and the object still comes later."""
    unit = _unit()
    assert unit.connect(0.0, until=1.5) == (None, 1.5, None)
    assert unit.connected is None and not unit.connections
    seq, due, connected = unit.connect(1.5)
    assert (seq, connected) == (1, True) and due == pytest.approx(3.0, abs=1e-3)
