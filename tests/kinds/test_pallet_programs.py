"""The stacking programs of every target against the float64 reference, and the mutations verify must catch."""

from pathlib import Path

import pytest
from support.programs import edited, sources, verify, verify_one

from codegen.model.cell import load_cell
from codegen.render import render

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
TARGETS = ("ur", "kuka", "abb", "dtrans")


@pytest.fixture(scope="module", params=["testmat_pallet.toml", "eur_pallet.toml"])
def cell(request):
    return load_cell(PALLETS / request.param)


@pytest.mark.parametrize("target", TARGETS)
def test_every_stacking_program_matches_the_reference(cell, target):
    """A full stack (or unstack), restarts at random boxes, a full (empty) pallet, counters out of range,
    a gripper that never closes or never opens: every move, gripper output, stop and the counters left."""
    if target not in cell.targets:
        pytest.skip(f"{cell.name} has no {target} program (the EUR cell has no UR: see its file)")
    for index, report in enumerate(verify(cell, sources(cell, target, "pallet"), cases=1)):
        assert report.cases >= 12 and report.mismatches == 0, report.first_mismatches
        assert report.figures.boxes >= cell.sections["pallet"][index].layers * 6  # the full stack at least


def _mutant_mismatches(cell, target: str, file_suffix: str, old: str, new: str) -> list[str]:
    """The first pallet's program with `old` replaced once in its file of that suffix: its first mismatch."""
    program = sources(cell, target, "pallet")[0]
    (own,) = [f for f in program.files if f.suffix == file_suffix]
    assert own.text.count(old) >= 1, f"{old!r} not in the {target} program"

    def edit(text: str) -> str:
        return text.replace(old, new, 1) if text == own.text else text

    return verify_one(cell, edited(program, edit), first_mismatch=True).first_mismatches


# (target, file, old, new): a wrong layer height, the cycle swapped, a counter that is not persistent, the
# angle turned the wrong way, the counters advanced before the release is confirmed (source 004's cell)
MUTATIONS = [
    ("ur", ".script", "PAL_HEIGHT = 26.0000", "PAL_HEIGHT = 25.0000"),
    ("ur", ".script", "PAL_CYCLE = [0, 1]", "PAL_CYCLE = [1, 0]"),
    ("ur", ".script", "pal_layer = read_input_integer_register(26)", "pal_layer = 1"),
    ("ur", ".script", "0, 0, d2r(a)]", "0, 0, d2r(-a)]"),
    (
        "ur",
        ".script",
        "    pal_release()\n    # the box is down",
        "    pal_box = pal_box + 1\n    write_output_integer_register(27, pal_box)\n    pal_box = pal_box - 1\n"
        "    pal_release()\n    # the box is down",
    ),
    ("kuka", ".dat", "PAL_HEIGHT=26.0000", "PAL_HEIGHT=25.0000"),
    ("kuka", ".dat", "PAL_CYCLE[1]=1\nPAL_CYCLE[2]=2", "PAL_CYCLE[1]=2\nPAL_CYCLE[2]=1"),
    ("kuka", ".src", "DECL INT PATTERN, ROW", "DECL INT PATTERN, ROW, PAL_LAYER, PAL_BOX"),  # not in the data list
    ("kuka", ".src", "BOX.A = PAL_A[ROW]", "BOX.A = -PAL_A[ROW]"),
    (
        "kuka",
        ".src",
        "    IF NOT PAL_RELEASE() THEN\n      RETURN ; the box is still in the gripper: the counters stay at it\n"
        "    ENDIF\n    ; the box is down (the sensor confirmed it): the next one\n    PAL_BOX = PAL_BOX + 1\n",
        "    PAL_BOX = PAL_BOX + 1\n    IF NOT PAL_RELEASE() THEN\n      RETURN\n    ENDIF\n",
    ),
    ("abb", ".mod", "STACK_HEIGHT := 26.0000;", "STACK_HEIGHT := 25.0000;"),
    ("abb", ".mod", "STACK_CYCLE{2} := [1, 2];", "STACK_CYCLE{2} := [2, 1];"),
    ("abb", ".mod", "LOCAL PERS num pal_layer := 1;", "LOCAL VAR num pal_layer := 1;"),  # reset at each start
    ("abb", ".mod", "OrientZYX(STACK_A{row} + STACK_A0", "OrientZYX(-STACK_A{row} + STACK_A0"),
    (
        "abb",
        ".mod",
        "      stack_release;\n      ! the box is down and the gripper open: the next box\n"
        "      pal_box := pal_box + 1;\n",
        "      pal_box := pal_box + 1;\n      stack_release;\n",
    ),
    ("dtrans", ".prg", "Double PAL_HEIGHT = 26.0000", "Double PAL_HEIGHT = 25.0000"),
    ("dtrans", ".prg", "Int PAL_CYCLE[2] = {0, 1}", "Int PAL_CYCLE[2] = {1, 0}"),
    ("dtrans", ".prg", "Int pattern = 0", "pal_layer = 1\nInt pattern = 0"),
    ("dtrans", ".prg", "PAL_TURN + a + PAL_TOOL_A", "PAL_TURN - a + PAL_TOOL_A"),
    (
        "dtrans",
        ".prg",
        "  Call pal_release()\n  // the box is down",
        "  pal_box = pal_box + 1\n  Call pal_release()\n  pal_box = pal_box - 1\n  // the box is down",
    ),
]


@pytest.mark.parametrize(("target", "suffix", "old", "new"), MUTATIONS)
def test_verify_fails_a_broken_stacking_program(target, suffix, old, new):
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    assert _mutant_mismatches(cell, target, suffix, old, new)


def test_every_target_has_its_mutations():
    assert {m[0] for m in MUTATIONS} == set(TARGETS) and all(sum(m[0] == t for m in MUTATIONS) >= 5 for t in TARGETS)


def test_a_program_that_ignores_the_automatic_approach_fails_verify():
    cell = load_cell(PALLETS / "eur_pallet.toml")
    found = _mutant_mismatches(cell, "kuka", ".src", "PAL_APPROACH.X = PAL_AX[ROW]", "PAL_APPROACH.X = 30.0")
    assert found and "approach" in found[0], found


def test_the_programs_move_the_cells_tool():
    """Source 004's cell names an arm and a 120 mm gripper: each program moves that tool, not the flange.
    RAPID's moves carry it (verify compares each move's tooldata); UR and KRL set it once at the start."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    files = {f.relpath.rsplit("/", 1)[1]: f.text for f in render(cell)}
    assert "set_tcp(p[0.0000000, 0.0000000, 0.1200000," in files["pal_testmat.script"]
    assert "  $TOOL = PAL_TOOL_DATA\n  $LOAD = PAL_LOAD\n" in files["pal_testmat.src"]
    assert "DECL FRAME PAL_TOOL_DATA={X 0.0000,Y 0.0000,Z 120.0000," in files["pal_testmat.dat"]
    found = _mutant_mismatches(
        cell, "abb", ".mod", "MoveL target, stack_work, fine, stack_tool", "MoveL target, stack_work, fine, tool0"
    )
    assert found and "tool" in found[0], found


def test_the_controllers_choice_of_joints_is_checked_against_the_plan():
    """With the arm, every run solves each move by the controller's rules and the configuration the program
    names (chosen by codegen per box and for Q). Without the program's home move the run lacks a move
    (the first motion then is the joint move above Q, in the configuration the program names: for KRL a
    valid BCO run, for RAPID a move with ConfJ on); a box named in another configuration (RAPID cfx,
    KRL Status, UR qnear) is refused or moves the arm otherwise than the plan."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = _mutant_mismatches(cell, "kuka", ".src", "  PTP PAL_HOME", "  ;PTP PAL_HOME")
    assert found and "moves, expected" in found[0], found
    found = _mutant_mismatches(cell, "abb", ".mod", "    MoveAbsJ stack_home", "    ! MoveAbsJ stack_home")
    assert found and "moves, expected" in found[0], found
    # box 1's configuration with axis 5 negative (cfx 1): the same pose with the wrist flipped
    conf = "STACK_CONF{12} := [[-1, 0, -2, "
    found = _mutant_mismatches(cell, "abb", ".mod", conf + "0]", conf + "1]")
    assert found and "cannot reach this pose in configuration [-1, 0, -2, 1]" in found[0], found
    # box 1's Status with the other A5 sign (bit 2)
    found = _mutant_mismatches(cell, "kuka", ".dat", "PAL_S[1]=2\n", "PAL_S[1]=6\n")
    assert found and "cannot reach this pose in configuration [6, 2]" in found[0], found
    # the same pose in another configuration (UR: the solution nearest another qnear): the joints differ
    wrist_flip = "qnear=[-0.3, -1.2, -1.8, -1.5, 1.57, 0.5]"
    found = _mutant_mismatches(cell, "ur", ".script", "qnear=pal_qnear(row)", wrist_flip)
    assert found and "entry, line" in found[0] and "the controller's rule gives [" in found[0], found


@pytest.mark.parametrize(
    ("target", "suffix", "old", "new"),
    [
        ("ur", ".script", "  if get_standard_digital_in(1) == True:\n", "  if False:\n"),
        ("kuka", ".src", "  IF $IN[18] THEN\n", "  IF FALSE THEN\n"),
        ("abb", ".mod", "    IF held THEN\n", "    IF FALSE THEN\n"),
        ("dtrans", ".prg", "If DIn(2) == True Then\n", "If False Then\n"),
    ],
)
def test_a_program_that_opens_a_gripper_holding_a_box_fails_verify(target, suffix, old, new):
    """Started with a box in the gripper (a cycle stopped on the way), the program must stop, not open it."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = _mutant_mismatches(cell, target, suffix, old, new)
    assert found and found[0].startswith("held_at_start"), found
