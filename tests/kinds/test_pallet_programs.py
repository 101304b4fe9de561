"""The pallet programs of every target against the float64 reference, and the mutations verify must catch."""

from pathlib import Path

import numpy as np
import pytest
from support.cells import EXAMPLES, example
from support.programs import edited, sources, verify, verify_one

from codegen.kinds.pallet.plan import configurations
from codegen.kinds.pallet.reach import joints_of, safe_move
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.shape import full_cycle
from codegen.model.cell import load_cell
from codegen.render import render

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
TARGETS = ("ur", "kuka", "abb", "dtrans")
OWN_SCENARIOS = {"part_missing", "pallet_absent", "pallet_taken", "counters_reloaded", "start_away", "start_mid_cycle"}


@pytest.fixture(scope="module", params=["testmat_pallet.toml", "eur_pallet.toml"])
def cell(request):
    return load_cell(PALLETS / request.param)


@pytest.mark.slow  # a whole verify run: in the slow set (the default run stays near 5 minutes)
@pytest.mark.parametrize("target", TARGETS)
def test_every_pallet_program_matches_the_reference(cell, target):
    """A full stack (or unstack), restarts at random boxes and at a slip sheet, a full (empty) pallet reset by the PLC
    or not, counters out of range, a gripper that never closes or never opens, a box, a sheet or the pallet that never
    comes, the counters after a reload, a start away from home and mid-cycle: every move, payload, gripper output,
    stop and the counters left; each pallet's scenarios run on every target."""
    if target not in cell.targets:
        pytest.skip(f"{cell.name} has no {target} program (the EUR cell has no UR: see its file)")
    rows = verify(cell, sources(cell, target, "pallet"), cases=1)
    for row in rows:
        assert row.cases >= 20 and row.mismatches == 0, row.first_mismatches
        assert set(row.scenarios) >= OWN_SCENARIOS, sorted(row.scenarios)
        need = 30 * len(cell.sections["pallet"]) if target == "abb" else 30  # the ABB task runs every pallet
        assert row.figures.boxes >= need, row.figures


def _named(program, name: str) -> list:
    return [f for f in program.files if f.name.rsplit("/", 1)[-1] == name]


def mutant_mismatches(cell, target: str, name: str, old: str, new: str, count: int = 1) -> list:
    """The program with the file of that name (a KRL data list, a task's module, a UR Script-node twin) with `old`
    replaced in that file (count 0: every one): its first mismatches."""
    program = next(p for p in sources(cell, target, "pallet") if _named(p, name))
    (own,) = _named(program, name)
    assert own.text.count(old) >= 1, f"{old!r} not in the {target} program's {name}"

    def edit(text: str) -> str:
        return text.replace(old, new, count if count else -1) if text == own.text else text

    return verify_one(cell, edited(program, edit), first_mismatch=True, clearance=False).first_mismatches


# (target, file, old, new): a wrong layer height, the cycle swapped, counters that do not come from their store (or a
# pallet frame 1 mm off), the angle turned the wrong way, the counters advanced before the release is confirmed
# (source 004's cell)
MUTATIONS = [
    ("ur", "pal_testmat.script", "PAL_HEIGHT = 26.0000", "PAL_HEIGHT = 25.0000"),
    ("ur", "pal_testmat.script", "PAL_CYCLE = [0, 1]", "PAL_CYCLE = [1, 0]"),
    ("ur", "pal_testmat.script", "pal_layer = read_input_integer_register(0)", "pal_layer = 1"),
    ("ur", "pal_testmat.script", "0, 0, d2r(a)]", "0, 0, d2r(-a)]"),
    (
        "ur",
        "pal_testmat.script",
        "    pal_release()\n    set_target_payload",
        "    pal_box = pal_box + 1\n    pal_report(pal_layer, pal_box)\n    pal_box = pal_box - 1\n"
        "    pal_release()\n    set_target_payload",
    ),
    ("kuka", "pal_testmat.dat", "PAL_HEIGHT=26.0000", "PAL_HEIGHT=25.0000"),
    ("kuka", "pal_testmat.dat", "PAL_CYCLE[1]=1\nPAL_CYCLE[2]=2", "PAL_CYCLE[1]=2\nPAL_CYCLE[2]=1"),
    (
        "kuka",
        "pal_testmat.src",
        "PAL_FRAME = INV_POS($ROBROOT) : BASE_DATA[1]\n",
        "PAL_FRAME = INV_POS($ROBROOT) : BASE_DATA[1] : {X 1.0,Y 0.0,Z 0.0,A 0.0,B 0.0,C 0.0}\n",
    ),
    ("kuka", "pal_testmat.src", "BOX.A = PAL_A[ROW]", "BOX.A = -PAL_A[ROW]"),
    (
        "kuka",
        "pal_testmat.src",
        "    IF NOT PAL_RELEASE() THEN\n"
        "      RETURN ; the box is still in the gripper: the counters stay at it, marked\n"
        "    ENDIF\n    PAL_TESTMAT_LAYER = -PAL_TESTMAT_LAYER\n    $LOAD = LOAD_DATA[1]\n    HELD = FALSE\n"
        "    ; the box is down (the sensor confirmed it): the next one\n    PAL_TESTMAT_BOX = PAL_TESTMAT_BOX + 1\n",
        "    PAL_TESTMAT_BOX = PAL_TESTMAT_BOX + 1\n    IF NOT PAL_RELEASE() THEN\n      RETURN\n    ENDIF\n"
        "    PAL_TESTMAT_LAYER = -PAL_TESTMAT_LAYER\n    $LOAD = LOAD_DATA[1]\n    HELD = FALSE\n",
    ),
    ("abb", "pal_testmat.mod", "STACK_HEIGHT := 26.0000;", "STACK_HEIGHT := 25.0000;"),
    ("abb", "pal_testmat.mod", "STACK_CYCLE{2} := [1, 2];", "STACK_CYCLE{2} := [2, 1];"),
    ("abb", "pallet_data.sys", "PERS num pal_testmat_layer := 1;", "VAR num pal_testmat_layer := 1;"),  # reset at main
    ("abb", "pallet_data.sys", "MODULE pallet_data(SYSMODULE)", "MODULE pallet_data"),  # a program load replaces it
    ("abb", "pal_testmat.mod", "OrientZYX(STACK_A{row} + STACK_A0", "OrientZYX(-STACK_A{row} + STACK_A0"),
    (
        "abb",
        "pal_testmat.mod",
        "      stack_release;\n      pal_testmat_layer := -pal_testmat_layer;\n      GripLoad load0;\n"
        "      held := FALSE;\n      ! the box is down and the gripper open: the next box\n"
        "      pal_testmat_box := pal_testmat_box + 1;\n",
        "      pal_testmat_box := pal_testmat_box + 1;\n      stack_release;\n"
        "      pal_testmat_layer := -pal_testmat_layer;\n      GripLoad load0;\n      held := FALSE;\n",
    ),
    ("dtrans", "pal_testmat.prg", "Double PAL_HEIGHT = 26.0000", "Double PAL_HEIGHT = 25.0000"),
    ("dtrans", "pal_testmat.prg", "Int PAL_CYCLE[2] = {0, 1}", "Int PAL_CYCLE[2] = {1, 0}"),
    ("dtrans", "pal_testmat.prg", "Int pattern = 0", "pal_layer = 1\nInt pattern = 0"),
    ("dtrans", "pal_testmat.prg", "PAL_TURN + a + PAL_TOOL_A", "PAL_TURN - a + PAL_TOOL_A"),
    (
        "dtrans",
        "pal_testmat.prg",
        "  Call pal_release()\n  pal_layer = 0 - pal_layer\n  held = 0\n  // the box is down",
        "  pal_box = pal_box + 1\n  Call pal_release()\n  pal_box = pal_box - 1\n  pal_layer = 0 - pal_layer\n"
        "  held = 0\n  // the box is down",
    ),
]


@pytest.mark.parametrize(("target", "name", "old", "new"), MUTATIONS)
def test_verify_fails_a_broken_pallet_program(target, name, old, new):
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    assert mutant_mismatches(cell, target, name, old, new)


def test_every_target_has_its_mutations():
    assert {m[0] for m in MUTATIONS} == set(TARGETS) and all(sum(m[0] == t for m in MUTATIONS) >= 5 for t in TARGETS)


def test_a_program_that_ignores_the_automatic_approach_fails_verify():
    cell = load_cell(PALLETS / "eur_pallet.toml")
    found = mutant_mismatches(cell, "kuka", "pal_eur.src", "PAL_APPROACH.X = PAL_AX[ROW]", "PAL_APPROACH.X = 30.0")
    assert found and "approach" in found[0], found


def test_the_programs_move_the_cells_tool():
    """Source 004's cell names an arm and a 120 mm gripper: each program moves that tool, not the flange.
    RAPID's moves carry it (verify compares each move's tooldata); UR and KRL set it once at the start."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    files = {f.relpath.rsplit("/", 1)[1]: f.text for f in render(cell)}
    assert "set_tcp(p[0.0000000, 0.0000000, 0.1200000," in files["pal_testmat.script"]
    # KRL: the controller's numbered tool and load the cell names ([cell.tool] numbered), verify's controller holding
    # the cell's tool there
    assert (
        "  $TOOL = TOOL_DATA[1]\n" in files["pal_testmat.src"]
        and "  $LOAD = LOAD_DATA[1]\n" in files["pal_testmat.src"]
    )
    assert "PAL_TOOL_DATA" not in files["pal_testmat.dat"]
    found = mutant_mismatches(
        cell,
        "abb",
        "pal_testmat.mod",
        "MoveL target, stack_work, fine, stack_tool",
        "MoveL target, stack_work, fine, tool0",
    )
    assert found and ("tool" in found[0] or "payload" in found[0]), found


def test_the_controllers_choice_of_joints_is_checked_against_the_plan():
    """With the arm, every run solves each move by the controller's rules and the configuration the program
    names (chosen by codegen per box and for Q). Without the program's home move the run lacks a move; a box named
    in another configuration (RAPID cfx, KRL Status, UR qnear) is refused or moves the arm otherwise than the plan."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    # without the home move the run lacks it (the first motion is then the joint target above Q)
    found = mutant_mismatches(cell, "kuka", "pal_testmat.src", "  PTP PAL_HOME", "  ;PTP PAL_HOME")
    assert found and "moves, expected" in found[0], found
    found = mutant_mismatches(cell, "abb", "pal_testmat.mod", "    MoveAbsJ stack_home", "    ! MoveAbsJ stack_home")
    assert found and "moves, expected" in found[0], found
    # the configuration check on: every box's robtarget carries Q's robconf (the program names none, its
    # quadrants being on boundaries), which boxes in other quadrants of axis 1 or 6 cannot take
    found = mutant_mismatches(cell, "abb", "pal_testmat.mod", "    ConfJ \\Off;", "    ConfJ \\On;")
    assert found and "cannot reach this pose in configuration" in found[0], found
    # box 1's Status with the other A5 sign (bit 2)
    # (the wrist flipped: axis 4 half a turn away either way, or axes 4 and 6 half a turn from the plan's)
    found = mutant_mismatches(cell, "kuka", "pal_testmat.dat", "PAL_S[1]=2\n", "PAL_S[1]=6\n")
    assert found and ("(180.000 deg apart" in found[0] or "the nearest solution is not unique" in found[0]), found
    # the same pose in another configuration (UR: the solution nearest another qnear): the joints differ
    wrist_flip = "qnear=[-0.3, -1.2, -1.8, -1.5, 1.57, 0.5]"
    found = mutant_mismatches(cell, "ur", "pal_testmat.script", "qnear=pal_qnear(row)", wrist_flip)
    assert found and "transit, line" in found[0] and "the controller's rule gives [" in found[0], found


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("ur", "pal_testmat.script", "  if not pal_held:   # the gripper opened", "  if True:   # the gripper opened"),
        ("kuka", "pal_testmat.src", "  IF NOT HELD THEN ; the gripper opened", "  IF TRUE THEN ; the gripper opened"),
        ("abb", "pal_testmat.mod", "    IF NOT held THEN\n      ! the gripper opened", "    IF TRUE THEN\n      ! the"),
        ("dtrans", "pal_testmat.prg", "If held == 0 Then\n  // the gripper opened", "If 0 == 0 Then\n  // the"),
    ],
)
def test_a_program_that_opens_a_gripper_holding_a_box_fails_verify(target, name, old, new):
    """Started with a box in the gripper (a cycle stopped on the way), the program must not open it at the start."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and found[0].startswith("held_at_start"), found


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("ur", "pal_testmat.script", "  pal_held = get_standard_digital_in(1) == True\n", "  pal_held = False\n"),
        ("kuka", "pal_testmat.src", "  HELD = $IN[18]\n", "  HELD = $IN[18]\n  IF HELD THEN\n    HALT\n  ENDIF\n"),
        ("abb", "pal_testmat.mod", "    held := DInput(diGripClosed) = 1;\n", "    held := FALSE;\n"),
        ("dtrans", "pal_testmat.prg", "  held = 1\n", "  Halt\n"),
    ],
)
def test_a_box_held_at_the_start_is_placed_where_the_counters_say(target, name, old, new):
    """Stacking, a box held at the start is the one the counters name (they move only after a confirmed release): the
    program carries it from home onto its place and goes on; one that stops there (as it once did), or takes it for
    an empty gripper, fails verify."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and found[0].startswith("held_at_start"), found


@pytest.mark.slow  # a whole verify per mutation: the slow set
@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("kuka", "pal_eur_in.src", "  IF HELD THEN\n    ; the box gripped", "  IF FALSE THEN\n    ; the box gripped"),
        ("abb", "pal_eur_in.mod", "    IF held THEN\n      ! the box gripped", "    IF FALSE THEN\n      ! the"),
        ("dtrans", "pal_eur_in.prg", "If held == 1 Then\n  // the box gripped", "If held == 2 Then\n  // the"),
    ],
)
def test_an_unstacking_program_puts_a_held_box_down_at_q_first(target, name, old, new):
    """Unstacking, a box held at the start left the pallet (the counters moved at the grip): it goes down at Q (Q
    clear waited for) before the next box, also when it was the last; without the put-down verify fails."""
    cell = load_cell(PALLETS / "eur_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and found[0].startswith("held_at_start"), found


PALLET_CELLS = [name for name in EXAMPLES if pallets_of(example(name))]


@pytest.mark.parametrize("name", PALLET_CELLS)
def test_the_safe_pose_continues_from_the_cycle_s_joints(name):
    """The way home's joint move above the pallet takes the solution the program names for it: every axis within
    half a turn of its value at the cycle's first entry onto the pallet, so the way there after a stop
    turns no axis the long way (a UR arm once turned its base a full turn there, stretched out above the table: the
    safe pose's joints were the ones nearest home)."""
    cell = example(name)
    checked = 0
    for target in cell.targets:
        for pallet in pallets_of(cell):
            named = configurations(cell, pallet, target)
            if named is None:
                continue
            where = f"{name} {target} {pallet.name}"
            moves = full_cycle(cell, pallet)
            cycle = joints_of(cell, target, moves, where, pallet, named)
            keys = [named.key(pallet, m) for m in moves]
            entry = next(q for key, q in zip(keys, cycle, strict=True) if isinstance(key, tuple))
            # from a stop at the first entry (a program naming no configuration there goes to the nearest)
            safe = joints_of(cell, target, [safe_move(cell, pallet)], where, pallet, named, start=entry)[0]
            turn = np.abs(safe - entry)
            assert np.max(turn) <= 180.0, f"{where}: the first entry -> safe turns axis {np.argmax(turn) + 1}: {turn}"
            checked += 1
    assert checked > 0


@pytest.mark.parametrize(
    ("target", "name", "old", "new"),
    [
        ("kuka", "pal_eur.src", "    PTP PAL_ABOVE_AXES\n", "    PTP PAL_ABOVE\n"),
        ("abb", "pal_eur.mod", "      MoveAbsJ stack_above_q_axes\\NoEOffs,", "      MoveJ stack_above_q,"),
    ],
)
def test_the_move_above_q_is_a_joint_target_where_the_nearest_turn_would_be_a_tie(target, name, old, new):
    """The EUR cell's home has axis 6 at 0 and above Q needs it at 180: a PTP naming no Turn (KRL) or a MoveJ with the
    configuration check off (RAPID) would turn it either way, by rounding. The program goes there in axis values;
    the pose instead is refused by verify as not unique."""
    cell = example("eur_pallet")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and "the nearest solution is not unique (axis 6 half a turn away either way" in found[0], found


# the ABB store loaded again from its file (as a reset of RAPID does) mid-pallet: a program without the known flag's
# check takes the file's layer 1 box 1 and swings into the part-built stack; a file saved with the flag TRUE makes the
# file's counters look current; a question without \MaxTime waits at the pendant for ever
KNOWN_MUTATIONS = [
    ("pal_testmat.mod", "    IF NOT pal_testmat_known THEN\n", "    IF FALSE THEN\n", "store_reloaded"),
    (
        "pallet_data.sys",
        "PERS bool pal_testmat_known := FALSE;",
        "PERS bool pal_testmat_known := TRUE;",
        "store_reloaded",
    ),
    (
        "pal_testmat.mod",
        " \\MaxTime:=60.0 \\BreakFlag:=unanswered;\n        IF unanswered <> 0 THEN",
        ";\n        IF unanswered <> 0 THEN",
        "stopped_in_release",
    ),
]


@pytest.mark.parametrize(("name", "old", "new", "scenario"), KNOWN_MUTATIONS)
def test_a_store_reloaded_from_its_file_never_starts_a_part_built_pallet(name, old, new, scenario):
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, "abb", name, old, new)
    assert found and scenario in found[0], found


# the move from the entry to the approach at the travel speed again, as the programs had it: the box comes down beside
# the layer's boxes at the travel speed (dtrans has no speeds)
APPROACH_AT_TRAVEL = [
    ("ur", "pal_testmat.script", "z + 5.0000, a), a=1.2, v=0.0500,", "z + 5.0000, a), a=1.2, v=0.2500,"),
    (
        "kuka",
        "pal_testmat.src",
        "    $VEL.CP = 0.0500 ; m/s, the cell's work speed (50.0 mm/s): the approach and the target\n"
        "    LIN APPROACH C_DIS\n",
        "    $VEL.CP = 0.2500\n    LIN APPROACH C_DIS\n    $VEL.CP = 0.0500\n",
    ),
    ("abb", "pal_testmat.mod", "STACK_AY{row}, 5.0000), stack_work,", "STACK_AY{row}, 5.0000), stack_travel,"),
]


@pytest.mark.parametrize(("target", "name", "old", "new"), APPROACH_AT_TRAVEL)
def test_the_approach_goes_at_the_work_speed(target, name, old, new):
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and "approach" in found[0] and "expected" in found[0], found  # the move's speed


# unstacking, a box dropped during the retreat: a program that does not read the gripper's sensor at Q counts it as
# taken (as the programs did, which moved the counters at the grip); one whose restart ignores the mark goes on as if
# the box had reached Q
DROPPED_ON_THE_WAY = [
    (
        "ur",
        "pal_testmat.script",
        "    if get_standard_digital_in(1) != True:   # the box lost",
        "    if False:   #",
        "box_lost",
    ),
    (
        "kuka",
        "pal_eur_in.src",
        "    IF NOT $IN[18] THEN ; the box no longer",
        "    IF FALSE THEN ; the box no longer",
        "box_lost",
    ),
    (
        "abb",
        "pal_eur_in.mod",
        "      IF DInput(diGripClosed) = 0 THEN\n        ! the box no",
        "      IF FALSE THEN\n        !",
        "box_lost",
    ),
    (
        "dtrans",
        "pal_eur_in.prg",
        "  If DIn(2) <> True Then\n    // the box no longer",
        "  If 1 == 2 Then\n    //",
        "box_lost",
    ),
    (
        "kuka",
        "pal_eur_in.src",
        "  IF PAL_EUR_IN_LAYER < 0 THEN ; a stop between",
        "  IF FALSE THEN ; a stop between",
        "stopped_on_the_way",
    ),
]


@pytest.mark.parametrize(("target", "name", "old", "new", "scenario"), DROPPED_ON_THE_WAY)
def test_an_unstacked_box_dropped_on_the_way_to_q_is_not_counted_as_taken(request, target, name, old, new, scenario):
    """UR on source 004's test cell unstacking (no bundled cell unstacks on UR), the others on the EUR cell's."""
    cell = request.getfixturevalue("unstacking") if target == "ur" else load_cell(PALLETS / "eur_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new)
    assert found and found[0].startswith(scenario), found


def _flag_before_grip(text: str, flag: str, grip: str) -> bool:
    """In the grip routine, the holds flag is set TRUE before the line that sets the gripper's output to grip."""
    lines = text.splitlines()
    routine = next(
        i for i, line in enumerate(lines) if line.strip() in ("LOCAL PROC stack_grip()", "DEFFCT BOOL PAL_GRIP()")
    )
    at = next(i for i, line in enumerate(lines) if i > routine and line.strip().startswith(grip))
    before = [line.strip() for line in lines[routine:at]]
    return any(line.startswith((f"{flag} := TRUE;", f"{flag} = TRUE")) for line in before)


# (target, file, the flag, the grip output's line as it starts)
GRIPPING_MARKS = [
    ("abb", "pal_eur.mod", "pal_eur_holds", "SetDO doGripClose, 1;"),
    ("abb", "pal_eur_in.mod", "pal_eur_in_holds", "SetDO doGripClose, 1;"),
    ("kuka", "pal_eur.src", "PAL_EUR_HOLDS", "$OUT[17] = TRUE"),
    ("kuka", "pal_eur_in.src", "PAL_EUR_IN_HOLDS", "$OUT[17] = TRUE"),
]


@pytest.mark.parametrize(("target", "name", "flag", "grip"), GRIPPING_MARKS)
def test_the_holds_flag_is_set_before_the_grip_output(target, name, flag, grip):
    """A stop between the grip output and the sensor's answer must leave what the gripper then holds marked as this
    program's item (else the next start stops with "the item held is another program's"). No verify run can stop a
    program between two of its statements, so this is checked on the text: the flag set TRUE before the output (and a
    program with the flag after it, as before, is refused by the same check)."""
    cell = load_cell(PALLETS / "eur_pallet.toml")
    (own,) = [f for p in sources(cell, target, "pallet") for f in _named(p, name)]
    assert _flag_before_grip(own.text, flag, grip)
    mark = f"{flag} := TRUE;" if target == "abb" else f"{flag} = TRUE"
    old_order = "\n".join(line for line in own.text.splitlines() if not line.strip().startswith(mark))
    assert not _flag_before_grip(old_order, flag, grip)


# a restart with a box held: the program goes straight from home onto the transit (as the programs did), without the
# move above the pallet's centre in the cycle's turns; the reference has that move (a program that names no turn at
# the transit would take the turn nearest home: tests/kinds/test_pallet_margin.py)
HELD_START_ANCHOR = [
    ("kuka", "pal_testmat.src", "      PTP PAL_SAFE_AXES ; the PTP to TRANSIT", "      ; the PTP to TRANSIT"),
    (
        "abb",
        "pal_testmat.mod",
        "        MoveAbsJ stack_safe_axes\\NoEOffs,",
        "        ! MoveAbsJ stack_safe_axes\\NoEOffs,",
    ),
    (
        "ur",
        "pal_testmat.script",
        "      movej(get_inverse_kin(PAL_SAFE, qnear=PAL_SAFE_QNEAR), a=1.2, v=0.25)\n",
        "      sync()\n",
    ),
    ("dtrans", "pal_testmat.prg", "    MovJ PAL_SAFE\n", "    // MovJ PAL_SAFE\n"),
]


@pytest.mark.parametrize(("target", "name", "old", "new"), HELD_START_ANCHOR)
def test_a_restart_with_a_box_held_goes_above_the_pallet_first(target, name, old, new):
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, target, name, old, new, count=0)
    assert found and found[0].startswith("held_at_start"), found
