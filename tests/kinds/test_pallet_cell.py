"""What a commissioning engineer needs of a pallet program: interlocks from the cell, counters a reload leaves, one ABB
task, the carried payload, blends, the way home, slip sheets placed, the UR's PLC registers and Script-node form,
messages within the controller's limit. Each a mutation verify catches or a refusal with the cell's key."""

import re
from pathlib import Path

import pytest
from support.programs import edited, sources, verify_one
from test_pallet_programs import mutant_mismatches

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.dialects.rapid import Rapid
from codegen.kinds.pallet.cases import PalletRun
from codegen.kinds.pallet.cycle import PalletCase
from codegen.kinds.pallet.judge import judge
from codegen.kinds.pallet.messages import all_messages, counters_message
from codegen.kinds.pallet.report import cycle_estimate
from codegen.kinds.pallet.setup import setup as pallet_setup
from codegen.model.cell import CellError, load_cell
from codegen.render import render
from codegen.verify.plan import Case

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
TESTMAT_TEXT = (PALLETS / "testmat_pallet.toml").read_text()
IO_TABLE = TESTMAT_TEXT[TESTMAT_TEXT.index("[pallet.io]") : TESTMAT_TEXT.index("[pallet.patterns]")]


@pytest.fixture(scope="module")
def testmat():
    return load_cell(PALLETS / "testmat_pallet.toml")


@pytest.fixture(scope="module")
def eur():
    return load_cell(PALLETS / "eur_pallet.toml")


def _load(tmp_path, text: str):
    path = tmp_path / "cell.toml"
    path.write_text(text)
    return load_cell(path)


# --- interlocks ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("target", "name", "old", "new", "case"),
    [
        (
            "ur",
            "pal_testmat.script",
            '      pal_wait_on(2, "pallet testmat: no box at the pick place for 10 s, still waiting")\n',
            "",
            "part_missing",
        ),
        (
            "ur",
            "pal_testmat.script",
            '    pal_wait(3, "pallet testmat: no pallet in place in 10 s")\n',
            "",
            "pallet_absent",
        ),
        ("kuka", "pal_testmat.src", "      IF NOT PAL_PART() THEN\n", "      IF FALSE THEN\n", "part_missing"),
        ("kuka", "pal_testmat.src", "      IF NOT PAL_PALLET() THEN\n", "      IF FALSE THEN\n", "pallet_absent"),
        (
            "abb",
            "pal_testmat.mod",
            "WaitDI diPartAtQ, 1 \\MaxTime:=STACK_WAIT \\TimeFlag:=late;",
            "late := FALSE;",
            "part_missing",
        ),
        (
            "abb",
            "pal_testmat.mod",
            "WaitDI diPalletIn, 1 \\MaxTime:=STACK_WAIT \\TimeFlag:=late;",
            "late := FALSE;",
            "pallet_absent",
        ),
        ("dtrans", "pal_testmat.prg", "  If DIn(3) <> True Then\n", "  If False Then\n", "part_missing"),
        ("dtrans", "pal_testmat.prg", "  If DIn(4) <> True Then\n", "  If False Then\n", "pallet_absent"),
    ],
)
def test_a_program_that_does_not_wait_for_an_interlock_fails(testmat, target, name, old, new, case):
    """Without the wait for the box at Q (or the pallet in place) the arm comes down on nothing: verify's case with
    that input off expects the stop with the operator's message (the pallet), or the message that it waits on and
    the wait (the box at Q, which comes only after that message), and the program moves on (or, the pallet's wait
    above Q left out, picks the box and stops only at the transit height, with another message)."""
    found = mutant_mismatches(testmat, target, name, old, new)
    said = ("expected a stop", "stop message", "no notification")
    assert found and found[0].startswith(case) and any(s in found[0] for s in said), found


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        (
            "ur",
            "pal_testmat.script",
            '    pal_wait(3, "pallet testmat: no pallet in place in 10 s, the box is in the gripper")',
            "",
        ),
        ("kuka", "pal_testmat.src", "    IF NOT PAL_PALLET_BOX() THEN", "    IF FALSE THEN"),
        (
            "abb",
            "pal_testmat.mod",
            "      WaitDI diPalletIn, 1 \\MaxTime:=STACK_WAIT \\TimeFlag:=late;\n      IF late THEN\n"
            '        stack_stop "pallet testmat: no pallet in place in 10 s, the box is in the gripper";',
            '      late := FALSE;\n      IF late THEN\n        stack_stop "";',
        ),
        (
            "dtrans",
            "pal_testmat.prg",
            '  If DIn(4) <> True Then\n    TPWrite 0, "pallet testmat: no pallet in place in 10 s, the box',
            '  If False Then\n    TPWrite 0, "x',
        ),
    ],
)
def test_a_program_that_carries_the_box_over_a_pallet_taken_away_fails(testmat, target, name, old, new):
    """The pallet taken away while the arm was at Q: without the second wait, at the transit height, the arm swings
    the box over where the pallet was (and stops only above Q for the next box); verify's pallet_taken case expects
    the stop at the transit height with the box held."""
    found = mutant_mismatches(testmat, target, name, old, new)
    expected = "expected 'pallet testmat: no pallet in place in 10 s, the box is in the gripper'"
    assert found and found[0].startswith("pallet_taken") and expected in found[0], found


@pytest.mark.slow  # a whole verify per mutation: the slow set
def test_the_sheet_waits_for_the_pallet_again_before_it_goes_over_it(eur):
    found = mutant_mismatches(eur, "kuka", "pal_eur.src", "      IF NOT PAL_PALLET_SHEET() THEN", "      IF FALSE THEN")
    expected = "expected 'pallet eur: no pallet in place in 10 s, the sheet is in the gripper'"
    assert found and found[0].startswith("pallet_taken pallet eur layer 3 box 0") and expected in found[0], found


@pytest.mark.slow  # a whole verify per mutation: the slow set
def test_the_unstacking_program_waits_for_a_clear_pick_place_and_stacking_for_a_sheet(eur):
    clear = "    IF NOT PAL_CLEAR() THEN\n      RETURN\n    ENDIF\n"  # in the cycle and before a held box's put-down
    found = mutant_mismatches(eur, "kuka", "pal_eur_in.src", clear, "", count=0)
    assert found and found[0].startswith("place_not_clear"), found
    found = mutant_mismatches(
        eur, "kuka", "pal_eur.src", "        IF NOT PAL_SHEET() THEN\n          RETURN\n        ENDIF\n", ""
    )
    assert found and found[0].startswith("sheet_missing"), found


def test_the_plcs_reset_restarts_a_swapped_pallet_only(testmat):
    """The reset input starts a full pallet again at layer 1, box 1; on a pallet not full it does nothing (a PLC bit
    left on must not make the arm place into occupied slots)."""
    ignored = "    if get_standard_digital_in(4) == True:\n"
    found = mutant_mismatches(testmat, "ur", "pal_testmat.script", ignored, "    if False:\n")
    assert found and found[0].startswith("pallet_changed"), found
    always = "  if not pal_valid(pal_layer, pal_box) and not (pal_layer == 6 and pal_box == 1):"
    reset = "  if get_standard_digital_in(4) == True:\n    pal_layer = 1\n    pal_box = 1\n  end\n" + always
    found = mutant_mismatches(testmat, "ur", "pal_testmat.script", always, reset)
    assert found and found[0].startswith("reset_ignored"), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize("target", ["ur", "kuka", "abb", "dtrans"])
def test_a_reset_counts_only_once_the_plc_drops_it_in_answer_to_the_done_output(testmat, target):
    """The handshake: a reset honoured without waiting for the PLC to drop it (a level left on) starts a full pallet
    again and fails the reset_held case; a program that never turns the done output off to answer gets no drop from
    the PLC and fails pallet_changed."""
    name, waited, skipped, answer = {
        "ur": (
            "pal_testmat.script",
            "      while get_standard_digital_in(4) == True:\n",
            "      while False:\n",
            "      set_standard_digital_out(2, False)\n",
        ),
        "kuka": (
            "pal_testmat.src",
            "      IF NOT PAL_RESET_OFF() THEN\n",
            "      IF FALSE THEN\n",
            "      $OUT[22] = FALSE\n",
        ),
        "abb": (
            "pal_testmat.mod",
            "        WaitDI diPalletReset, 0 \\MaxTime:=STACK_WAIT \\TimeFlag:=late;\n",
            "        late := FALSE;\n",
            "        SetDO doPalletFull, 0;\n",
        ),
        "dtrans": ("pal_testmat.prg", "    While DIn(5) == True\n", "    While False\n", "    SetDO 3, False\n"),
    }[target]
    every = 0 if target == "abb" else 1  # ABB: the handshake of a store reloaded from its file, too
    found = mutant_mismatches(testmat, target, name, waited, skipped, every)
    assert found and found[0].startswith("reset_held"), found
    found = mutant_mismatches(testmat, target, name, answer, "", every)
    assert found and found[0].startswith("pallet_changed"), found


def test_a_reset_without_its_done_output_is_refused_by_key(tmp_path):
    text = TESTMAT_TEXT.replace('done = { ur = 2, kuka = 22, abb = "doPalletFull", dtrans = 3 }', "# no done output", 1)
    assert text != TESTMAT_TEXT
    with pytest.raises(CellError, match=r"pallet\[0\]\.io\.done: missing: the output the \w+ program turns off"):
        _load(tmp_path, text)


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        (IO_TABLE, "", r"pallet\[0\]\.io: missing: the inputs the program waits for"),
        ("part_present = {", "place_clear = {", r"pallet\[0\]\.io\.place_clear: not an input of a stacking pallet"),
        ("pallet_present = { ur = 3,", "pallet_present = { ur = 9,", r"pallet\[0\]\.io\.pallet_present\.ur: expected"),
        ("timeout_s = 10.0\n", "timeout_s = 0.1\n", r"pallet\[0\]\.io\.timeout_s: must be in \[0\.5, 600\] s"),
        (
            "zone_mm = 2.0 ",
            "zone_mm = 5.0 ",
            r"pallet\[0\]\.zone_mm: 5 mm is more than half of the 8\.7 mm of layer 1 box 1: approach to target",
        ),
        (
            "pick_lift = 30.0 ",
            'mode = "unstack"\nslip_sheet = { every = 2, thickness = 3.0 }\npick_lift = 30.0 ',
            "slip_sheet: an unstacking",
        ),
        (
            "pick_lift = 30.0 ",
            "slip_sheet = { every = 2, thickness = 3.0 }\npick_lift = 30.0 ",
            r"slip_sheet\.pick: missing",
        ),
    ],
)
def test_a_pallet_without_its_interlocks_or_with_a_zone_past_its_poses_is_refused_by_key(tmp_path, old, new, says):
    assert old in TESTMAT_TEXT
    with pytest.raises(CellError, match=says):
        _load(tmp_path, TESTMAT_TEXT.replace(old, new, 1))


# --- counters that a reload leaves ------------------------------------------------------------------------------


def test_the_counters_are_declared_in_their_store_alone(testmat, eur):
    """KRL: GLOBAL in the data list <pallet>_count.dat; RAPID: PERS in the system module pallet_data.sys; nowhere in
    a file a regeneration replaces (loading it again would set them back)."""
    for cell in (testmat, eur):
        files = {f.relpath: f.text for f in render(cell, ["kuka", "abb"])}
        for path, text in files.items():
            declared = re.findall(
                r"^\s*(?:DECL\b[^\n]*|(?:LOCAL\s+)?(?:PERS|VAR)\s+num)\s+(PAL_(?:TESTMAT|EUR|EUR_IN)_(?:LAYER|BOX))\b",
                text,
                re.M | re.I,
            )
            store = path.endswith("_count.dat") or path.endswith("pallet_data.sys")
            assert bool(declared) == store, (path, declared)


@pytest.mark.slow  # a whole verify per mutation: the slow set
def test_counters_moved_into_the_regenerated_program_fail_the_reload(testmat):
    """Declared in the program's own .dat (KRL) or module (RAPID), the counters would start again at their declared
    values when a regenerated program is loaded: the counters_reloaded case fails though every restart passes."""
    program = sources(testmat, "kuka", "pallet")[0]

    def krl(text: str) -> str:
        text = text.replace("DECL GLOBAL INT PAL_TESTMAT_LAYER=1\nDECL GLOBAL INT PAL_TESTMAT_BOX=1\n", "")
        return text.replace(
            "DECL REAL PAL_HEIGHT=", "DECL INT PAL_TESTMAT_LAYER=1\nDECL INT PAL_TESTMAT_BOX=1\nDECL REAL PAL_HEIGHT="
        )

    found = verify_one(testmat, edited(program, krl), first_mismatch=True, clearance=False).first_mismatches
    assert found and found[0].startswith("counters_reloaded") and "pal_testmat.dat" in found[0], found
    program = sources(testmat, "abb", "pallet")[0]

    def rapid(text: str) -> str:
        text = text.replace("  PERS num pal_testmat_layer := 1;\n  PERS num pal_testmat_box := 1;\n", "")
        counters = "  LOCAL PERS num pal_testmat_layer := 1;\n  LOCAL PERS num pal_testmat_box := 1;\n"
        return text.replace("  LOCAL CONST jointtarget stack_home", counters + "  LOCAL CONST jointtarget stack_home")

    found = verify_one(testmat, edited(program, rapid), first_mismatch=True, clearance=False).first_mismatches
    assert found and found[0].startswith("counters_reloaded") and "pal_testmat.mod" in found[0], found


def test_the_ur_counters_are_plc_data_on_fieldbus_registers(testmat):
    """Input integer registers 0..23 are the fieldbus PLC's, 24..47 the RTDE clients' (URScript manual): the
    counters are in 0 and 1 (10 pallets up to 19: 21-23 hold the belt's queue, [program.conveyor]); a program
    reading them from the RTDE range finds nothing and stops."""
    facts = get_target("ur").kind_tables["pallet"]
    belt = get_target("ur").kind_tables["conveyor"]["registers"]
    assert facts["registers"] == 0 and facts["registers_max"] == 20
    assert facts["registers_max"] < min(belt[k] for k in ("seq", "count", "encoder", "ack"))
    text = sources(testmat, "ur", "pallet")[0].files[0].text
    assert "read_input_integer_register(0)" in text and "write_output_integer_register(1, box)" in text
    found = mutant_mismatches(
        testmat, "ur", "pal_testmat.script", "read_input_integer_register(0)", "read_input_integer_register(24)"
    )
    assert found, found


def test_a_dtrans_reload_clears_the_counters_and_the_program_stops(testmat):
    """The dtrans dialect keeps nothing across a reload (its globals are declared without a value): the reload case
    expects the stop at the counter check, before any move."""
    source = sources(testmat, "dtrans", "pallet")[0]
    case = Case("counters_reloaded", PalletRun(0, PalletCase("counters_reloaded", 2, 3)))
    assert pallet_setup(testmat, source, case).inputs == {}
    (expectation,) = judge(testmat, source, case, None).accepted
    assert expectation.halt == counters_message(testmat.sections["pallet"][0], 80) and expectation.moves == ()


# --- one ABB task -------------------------------------------------------------------------------------------------


def test_the_abb_pallet_programs_are_one_task_with_one_main(eur):
    """pallet_main.mod has the task's one PROC main and starts the pallet whose select input is on; each pallet's
    module has one global routine; RAPID's loader takes the four modules as one task (two mains would be refused)."""
    files = [SourceFile(f.relpath, f.text) for f in render(eur, ["abb"])]
    assert [f.name.rsplit("/", 1)[1] for f in files] == [
        "pallet_main.mod",
        "pal_eur.mod",
        "pal_eur_in.mod",
        "pallet_data.sys",
    ]
    assert sum(len(re.findall(r"^\s*PROC main\(\)", f.text, re.M)) for f in files) == 1
    (task,) = Rapid.programs(files)
    assert task[0].name.endswith("pallet_main.mod")
    for f in files[1:3]:
        assert len(re.findall(r"^  PROC \w+\(\)", f.text, re.M)) == 1  # the entry; every other routine LOCAL
    twice = files[1].text.replace("  PROC pal_eur_run()", "  PROC main()\n  ENDPROC\n\n  PROC pal_eur_run()")
    with pytest.raises(Exception, match="both define PROC main"):
        Rapid.programs([files[0], SourceFile(files[1].name, twice), *files[2:]])


def test_two_krl_pallet_programs_share_a_controller_without_a_clash(eur):
    """Given together, as a controller holds them, the EUR cell's KRL files are two programs, each loading beside the
    other's modules: their routines and data are local to their modules but the counters, named per pallet."""
    from codegen.dialects import get_dialect

    files = [SourceFile(f.relpath, f.text) for f in render(eur, ["kuka"])]
    krl = get_dialect("krl")
    programs = krl.programs(files)
    assert [p[0].name.rsplit("/", 1)[1] for p in programs] == ["pal_eur.src", "pal_eur_in.src"]
    for program in programs:
        assert len(program) == 4  # its .src and .dat, and both pallets' counter data lists (GLOBAL, named apart)
        krl.load_files(program)


@pytest.mark.slow  # a whole verify run: in the slow set (the default run stays near 5 minutes)
def test_the_task_starts_the_selected_pallet_and_none_without_a_selection(eur):
    found = mutant_mismatches(eur, "abb", "pallet_main.mod", "DInput(diRunEur) = 1", "DInput(diRunEurIn) = 1")
    assert found, found
    found = mutant_mismatches(
        eur,
        "abb",
        "pallet_main.mod",
        '      ErrWrite "Pallet program stopped"',
        '      pal_eur_run;\n      ErrWrite "x"',
    )
    assert found and any(line.startswith("none_selected") for line in found), found


# --- the carried payload --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        (
            "ur",
            "pal_testmat.script",
            "      set_target_payload(0.850, [0.0000000, 0.0000000, 0.0548824], "
            "[0.001415, 0.001423, 0.000264, 0.000000, 0.000000, 0.000000])   # the tool and the box\n",
            "",
        ),
        ("kuka", "pal_testmat.src", "    $LOAD = PAL_LOAD_BOX\n", ""),
        ("abb", "pal_testmat.mod", "      GripLoad stack_box;\n", ""),
        # on before the grip is confirmed, or left on after the release
        ("kuka", "pal_testmat.src", "    LIN PAL_PICK\n", "    $LOAD = PAL_LOAD_BOX\n    LIN PAL_PICK\n"),
        (
            "abb",
            "pal_testmat.mod",
            "      pal_testmat_layer := -pal_testmat_layer;\n      GripLoad load0;\n",
            "      pal_testmat_layer := -pal_testmat_layer;\n",
        ),
    ],
)
def test_the_box_payload_is_in_force_from_the_grip_to_the_release(testmat, target, name, old, new):
    """The tool and the box (0.8 + 0.05 kg, their common centre of gravity) from the confirmed grip to the
    confirmed release: verify compares the payload in force at every move with the plan's."""
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and "payload" in found[0], found


# --- blends ----------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("kuka", "pal_testmat.src", "    LIN TARGET ; no approximation", "    LIN TARGET C_DIS ; no approximation"),
        (
            "abb",
            "pal_testmat.mod",
            "STACK_AY{row}, 5.0000), stack_work, stack_zone,",
            "STACK_AY{row}, 5.0000), stack_work, fine,",
        ),
        ("ur", "pal_testmat.script", "z + 5.0000, a), a=1.2, v=0.0500, r=0.0020)", "z + 5.0000, a), a=1.2, v=0.0500)"),
    ],
)
def test_travel_blends_and_the_arm_stops_at_pick_place_and_contact(testmat, target, name, old, new):
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and ("approx" in found[0] or "zone" in found[0] or " r " in found[0]), found


def test_the_cycle_estimate_counts_the_stops_and_the_blended_corners(eur):
    """Each blended pose shortens the path by the zone's corner; the estimate names its stops and blends."""
    estimate = cycle_estimate(eur, eur.sections["pallet"][0])
    assert estimate["blends"] > 0 and estimate["stops"] > 0 and estimate["corner_saving_mm"] > 0


def test_the_testmat_cycle_stops_at_pick_place_and_the_handshake_alone(testmat):
    """30 boxes of 10 moves, 29 of them 2 more (from the entry before over Q, then down above Q) and the 2 moves off
    the pallet (331): each box stops above Q before going down and after coming up (the Q handshake's outputs are set
    there, at a standstill), at Q and at its target, the last move stops above Q (121 stops); every other pose
    blends (210)."""
    estimate = cycle_estimate(testmat, testmat.sections["pallet"][0])
    assert (estimate["stops"], estimate["blends"]) == (121, 331 - 121)


# --- the way home -----------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("ur", "pal_testmat.script", "  if pal_away:\n", "  if False:\n"),
        ("kuka", "pal_testmat.src", "    BACK = $POS_ACT : PAL_BACK\n", "    BACK = $POS_ACT\n"),
        ("abb", "pal_testmat.mod", "      MoveAbsJ stack_safe_axes\\NoEOffs, stack_travel, fine, stack_tool;\n", ""),
    ],
)
def test_after_a_stop_the_program_backs_out_and_goes_home_above_the_pallet(testmat, target, name, old, new):
    """Started away from home or where a stop left it (at a box's target), the program moves where the arm stands,
    back along the tool's z, above the pallet's centre and home before the cycle."""
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and found[0].startswith(("start_away", "start_mid_cycle")), found


def test_the_full_message_comes_with_the_arm_off_the_pallet(testmat):
    above = "      LIN PAL_ABOVE\n      IF NOT PAL_SWAP() THEN\n"  # the done pallet's swap waited for above Q
    found = mutant_mismatches(testmat, "kuka", "pal_testmat.src", above, "      IF NOT PAL_SWAP() THEN\n")
    assert found, found
    found = mutant_mismatches(testmat, "kuka", "pal_testmat.src", "      PTP HIGH\n      $VEL.CP", "      $VEL.CP")
    assert found, found


# --- slip sheets ------------------------------------------------------------------------------------------------------


def test_slip_sheets_are_placed_from_the_dispenser(eur):
    """The EUR pallet's sheets: box 0 of layers 3 and 5, taken from the dispenser and put on the layer below at the
    pallet's centre; one not placed, or placed at the wrong height, fails."""
    found = mutant_mismatches(
        eur,
        "kuka",
        "pal_eur.src",
        "BOX.Z = PAL_TOP(PAL_EUR_LAYER - 1) + PAL_SLIP",
        "BOX.Z = PAL_TOP(PAL_EUR_LAYER - 1)",
    )
    assert found and "position error" in found[0], found
    found = mutant_mismatches(eur, "abb", "pal_eur.mod", "\n          pal_eur_box := 0;\n", "\n")
    assert found, found


SHEETS = TESTMAT_TEXT.replace(
    "zone_mm = 2.0 ",
    "slip_sheet = { every = 2, thickness = 3.0, pick = [450.0, 300.0, 50.0, 0.0, 0.0, 180.0], lift = 30.0 }\n"
    "zone_mm = 2.0 ",
    1,
).replace(
    "timeout_s = 10.0", 'sheet_ready = { ur = 5, kuka = 22, abb = "diSheetReady", dtrans = 6 }\ntimeout_s = 10.0', 1
)


@pytest.mark.slow  # a whole verify per mutation: the slow set
def test_the_ur_program_places_slip_sheets(tmp_path):
    """The EUR cell has no UR: source 004's pallet with a sheet on every second layer runs every case on the UR (the
    sheet missing, a restart at a sheet); a sheet put down 3 mm low, or never put down, fails."""
    cell = _load(tmp_path, SHEETS)
    program = sources(cell, "ur", "pallet")[0]
    row = verify_one(cell, program, cases=1)
    assert row.mismatches == 0 and {"part_missing", "restart"} <= set(row.scenarios), row.first_mismatches
    for old, new in [
        ("z = pal_top(pal_layer - 1) + PAL_SLIP", "z = pal_top(pal_layer - 1)"),
        ("      if pal_sheet_below(pal_layer):\n        pal_box = 0", "      if False:\n        pal_box = 0"),
    ]:
        assert old in program.files[0].text, old
        mutant = edited(program, lambda text, old=old, new=new: text.replace(old, new))
        assert verify_one(cell, mutant, cases=1, first_mismatch=True, clearance=False).first_mismatches, old


# --- the UR forms, the release, messages ---------------------------------------------------------------------------


def test_the_ur_script_node_twin_is_a_program_of_its_own(testmat):
    programs = sources(testmat, "ur", "pallet")
    assert [p.ident for p in programs] == ["pal_testmat", "pal_testmat_node"]
    assert "def pal_testmat():" not in programs[1].files[0].text and "needs PolyScope 5.10" in programs[1].files[0].text
    found = mutant_mismatches(testmat, "ur", "pal_testmat_node.script", "PAL_HEIGHT = 26.0000", "PAL_HEIGHT = 25.0000")
    assert found, found


def test_a_long_pallet_name_is_shortened_in_the_messages_never_the_instruction(tmp_path):
    """KRL's Msg_txt and RAPID's strings hold 80 characters: where a pallet's name would make a message longer, the
    message shows the name's start and "...", then all of what the operator must do (a cut end would hide it); every
    program of the cell shows that text, and verify expects it."""
    long = "a" * 40
    cell = _load(tmp_path, TESTMAT_TEXT.replace('name = "testmat"', f'name = "{long}"', 1))
    files = render(cell, ["kuka", "abb", "ur"])
    want = "pallet " + "a" * 15 + "...: no pallet in place in 10 s, the box is in the gripper"  # 80 characters
    assert len(want) == 80 and sum(want in f.text for f in files) == 4  # .src, the ABB module, both UR forms
    messages = all_messages(cell.sections["pallet"][0], 80)
    assert all(len(m) <= 80 and (long in m or len(m) == 80) for m in messages), messages  # shortened to fit only
    for f in render(load_cell(PALLETS / "eur_pallet.toml"), ["kuka", "abb"]):
        for message in re.findall(r'(?:MSG_TXT\[\] = |stack_stop |TPWrite )"([^"]*)"', f.text):
            assert len(message) <= 80 and "..." not in message, message


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        (
            "kuka",
            "pal_testmat.src",
            "      PAL_PAR[1] = {PAR_TYPE #EMPTY}\n      GAP = SET_KRLMSG(#STATE, PAL_MSG, PAL_PAR[], PAL_OPT)\n",
            "      PAL_HALT()\n      RETURN FALSE\n",
        ),
        (
            "abb",
            "pal_testmat.mod",
            "          WHILE late DO\n",
            '          stack_stop "no box";\n          WHILE late DO\n',
        ),
        ("ur", "pal_testmat.script", "pal_wait_on(2, ", "pal_wait(2, "),
        ("dtrans", "pal_testmat.prg", "      While DIn(3) <> True\n", "      Halt\n      While DIn(3) <> True\n"),
    ],
)
def test_a_gap_in_the_infeed_is_waited_out_with_a_message(testmat, target, name, old, new):
    """No box at the pick place for the timeout: the program tells the operator once and waits on (a palletizer's
    infeed has gaps); verify's part_missing case brings the box only after that message. A program that stops there
    (as it once did) fails."""
    found = mutant_mismatches(testmat, target, name, old, new)
    assert found and found[0].startswith("part_missing"), found


# --- a stop during a release ------------------------------------------------------------------------------------------


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "mark"),
    [
        ("ur", "pal_testmat.script", "    pal_report(-pal_layer, pal_box)   # marked"),
        ("kuka", "pal_testmat.src", "    PAL_TESTMAT_LAYER = -PAL_TESTMAT_LAYER ; marked"),
        ("abb", "pal_testmat.mod", "      pal_testmat_layer := -pal_testmat_layer;\n      stack_release;"),
        ("dtrans", "pal_testmat.prg", "  pal_layer = 0 - pal_layer  // marked"),
    ],
)
def test_the_counters_are_marked_while_a_box_is_released(testmat, target, name, mark):
    """Before the gripper opens at the target the counters are marked (the layer negative), so a stop before the
    sensor confirms the release is found at the next start; a program without the mark fails verify (a stuck
    gripper leaves the counters unmarked)."""
    unmarked = {"ur": "    #", "kuka": "    ;", "abb": "      stack_release;", "dtrans": "  //"}[target]
    found = mutant_mismatches(testmat, target, name, mark, unmarked)
    assert found, found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "answered", "ignored"),
    [
        (
            "ur",
            "pal_testmat.script",
            'request_boolean_from_primary_client("pallet testmat: stopped in a release. Is the item down? No: remove '
            'it first")',
            "False",
        ),
        ("kuka", "pal_testmat.src", "      ANSWER = PAL_ASK()\n", "      ANSWER = 2\n"),
        ("abb", "pal_testmat.mod", "        IF answer = 1 THEN\n", "        IF FALSE THEN\n"),
    ],
)
def test_after_a_stop_in_a_release_the_operator_decides_whether_the_item_is_down(
    testmat, target, name, answered, ignored
):
    """The operator's Yes moves the counters on (the box is down, also past the last box: the pallet full); a program
    that does not ask, or ignores the answer, places the box again onto the one already there."""
    found = mutant_mismatches(testmat, target, name, answered, ignored)
    assert found and found[0].startswith("stopped_in_release"), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "undo"),
    [
        (
            "ur",
            "pal_testmat.script",
            "        set_standard_digital_out(0, False)   # the grip not confirmed: the gripper",
        ),
        ("kuka", "pal_testmat.src", "      $OUT[17] = FALSE ; the grip not confirmed: the gripper"),
        ("abb", "pal_testmat.mod", "      SetDO doGripClose, 0;\n      pal_testmat_holds := FALSE;\n      stack_stop"),
        ("dtrans", "pal_testmat.prg", "      SetDO 1, False  // the grip not confirmed: the gripper"),
    ],
)
def test_a_grip_not_confirmed_opens_the_gripper_before_the_stop(testmat, target, name, undo):
    """A vacuum left on after the grip's timeout would lift a box held below the sensor's threshold on the way home;
    a program that stops without opening the gripper again fails the gripper_silent case."""
    kept = {"abb": "      stack_stop"}.get(target, "      ;")  # the line left as a comment
    comment = {"ur": "#", "kuka": ";", "dtrans": "//"}.get(target)
    found = mutant_mismatches(testmat, target, name, undo, kept if comment is None else f"      {comment} removed:")
    assert found and found[0].startswith("gripper_silent"), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "check", "grip"),
    [
        (
            "kuka",
            "pal_testmat.src",
            "  IF HELD AND NOT PAL_TESTMAT_HOLDS THEN",
            "  PAL_TESTMAT_HOLDS = TRUE ; gripping",
        ),
        ("abb", "pal_testmat.mod", "    IF held AND NOT pal_testmat_holds THEN", "    pal_testmat_holds := TRUE;"),
    ],
)
def test_an_item_another_program_gripped_is_not_taken_for_this_pallets(testmat, target, name, check, grip):
    """The store's flag says which program gripped what the gripper holds: a program that does not look at it takes
    another pallet's item for its own (held_by_another); one that never sets it at the grip leaves the flag wrong
    after a stop with the item held (gripper_stuck_at_target)."""
    unchecked = check.replace(" AND NOT", " AND FALSE AND NOT")
    found = mutant_mismatches(testmat, target, name, check, unchecked)
    assert found and found[0].startswith("held_by_another"), found
    unset = grip.replace("TRUE", "FALSE")
    found = mutant_mismatches(testmat, target, name, grip, unset)
    assert found and any(f.startswith("gripper_stuck_at_target") for f in found), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "check", "unchecked"),
    [
        (
            "ur",
            "pal_testmat.script",
            "    if get_standard_digital_in(1) != True:   # the item",
            "    if False:   # the item",
        ),
        ("kuka", "pal_testmat.src", "    IF NOT $IN[18] THEN ; the item", "    IF FALSE THEN ; the item"),
        ("abb", "pal_testmat.mod", "      IF DInput(diGripClosed) = 0 THEN\n", "      IF FALSE THEN\n"),
        ("dtrans", "pal_testmat.prg", "  If DIn(2) <> True Then\n    // the item", "  If False Then\n    // the item"),
    ],
)
def test_a_box_lost_on_the_way_is_not_counted_as_placed(testmat, target, name, check, unchecked):
    """Before the release the gripper's sensor must still see the box: a program that does not look releases an
    empty gripper, sees it open at once and counts the box as placed (a hole the next layer bridges)."""
    found = mutant_mismatches(testmat, target, name, check, unchecked)
    assert found and found[0].startswith("box_lost"), found


def test_an_unstacking_pallet_whose_wait_above_q_would_hang_the_box_into_one_at_q_is_refused(tmp_path):
    """Unstacking, the program waits above Q for Q clear with a box in the gripper: above Q must clear a box still
    lying there (pick_lift >= the box's height + transit_clearance_mm), named by key."""
    text = (PALLETS / "eur_pallet.toml").read_text()
    low = text.replace("pick_lift = 300.0 ", "pick_lift = 100.0 ", 1)
    assert low != text
    with pytest.raises(CellError, match=r"pallet\[1\]\.pick_lift: 100 mm: unstacking.*160 mm too low"):
        _load(tmp_path, low)


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "grip"),
    [
        ("ur", "pal_testmat.script", "  if pal_held:   # an item held since a stop"),
        ("kuka", "pal_testmat.src", "  IF HELD THEN ; an item held since a stop"),
        ("abb", "pal_testmat.mod", "    IF held THEN\n      ! an item held since a stop"),
        ("dtrans", "pal_testmat.prg", "If held == 1 Then\n  SetDO 1, True"),
    ],
)
def test_an_item_held_at_the_start_is_gripped_again_before_the_arm_moves(testmat, target, name, grip):
    """A stop (or a release that did not finish) may leave the gripper's output off with the item still in it: the
    program sets it to grip before the way home; one that does not carries the item on a decaying grip."""
    never = {
        "ur": "  if False:   # an item held since a stop",
        "kuka": "  IF FALSE THEN ; an item held since a stop",
        "abb": "    IF FALSE THEN\n      ! an item held since a stop",
        "dtrans": "If False Then\n  SetDO 1, True",
    }[target]
    found = mutant_mismatches(testmat, target, name, grip, never)
    assert found and found[0].startswith("held_at_start"), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "clear"),
    [
        ("abb", "pal_eur.mod", "    pal_eur_in_holds := FALSE;\n"),
        ("kuka", "pal_eur.src", "  PAL_EUR_IN_HOLDS = FALSE ;"),
    ],
)
def test_a_grip_clears_the_other_pallets_flags_of_the_arm(eur, target, name, clear):
    """One arm runs both EUR pallets (one ABB task; KUKA programs sharing their GLOBAL count data lists): a grip of one
    program clears the other's flag, else a flag left set (its item taken out of the gripper by hand) would make this
    program's item look like the other's after a stop."""
    found = mutant_mismatches(eur, target, name, clear, "" if target == "abb" else "  ;")
    assert found and found[0].startswith("stale_flag"), found


@pytest.mark.slow  # a whole verify per target and mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "rise"),
    [("kuka", "pal_eur.src", "    IF BACK.Z < "), ("abb", "pal_eur.mod", "      IF back.trans.z < ")],
)
def test_the_way_home_rises_over_every_pallet_of_the_arm(eur, target, name, rise):
    """A stop over the bottom layer of one pallet: the way home rises straight up to the transit height over the
    highest full stack of the arm's pallets before its joint move (the other pallet may be full); a program that
    rises only to its own layer's transit height, or not at all, fails the way home (start_away, start_mid_cycle)."""
    never = rise.replace("IF ", "IF FALSE AND ")
    found = mutant_mismatches(eur, target, name, rise, never)
    assert found and found[0].startswith(("start_mid_cycle", "start_away")), found
