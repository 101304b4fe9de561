"""The pallet programs' vendor findings: KUKA's tool and pallet frames from the controller's numbered data, a grip
that clears the other pallets' flags, and the texts the commissioning engineer reads (questions, messages, headers)."""

from pathlib import Path

import pytest
from support.cells import example
from support.programs import edited, sources, verify_one

from codegen.model.cell import load_cell
from codegen.model.validate import CellError
from codegen.render import render

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"


@pytest.fixture(scope="module")
def testmat():
    return example("testmat_pallet")


@pytest.fixture(scope="module")
def eur():
    return example("eur_pallet")


def _mismatches(cell, target: str, name: str, old: str, new: str) -> list:
    """The first mismatches of the program whose file `name` has `old` replaced by `new` (each occurrence)."""
    program = next(p for p in sources(cell, target, "pallet") if any(f.name.endswith(name) for f in p.files))
    (own,) = [f for f in program.files if f.name.rsplit("/", 1)[-1] == name]
    assert old in own.text, f"{old!r} not in the {target} program's {name}"
    mutant = edited(program, lambda t: t.replace(old, new) if t == own.text else t)
    return verify_one(cell, mutant, first_mismatch=True, clearance=False).first_mismatches


def _files(cell) -> dict[str, str]:
    return {f.relpath: f.text for f in render(cell)}


BASE_CHECK_START = "  ; the pallet frame as measured into BASE_DATA[1]"
BASE_CHECK_END = "  $TOOL = TOOL_DATA[1]\n"


@pytest.mark.slow  # a verify per mutation: the slow set
@pytest.mark.parametrize(
    ("old", "new"),
    [
        # another base: verify's controller holds the pallet's frame in BASE_DATA[1] alone (the others fresh: zero)
        ("PAL_FRAME = INV_POS($ROBROOT) : BASE_DATA[1]", "PAL_FRAME = INV_POS($ROBROOT) : BASE_DATA[2]"),
        # another tool: TOOL_DATA[2] fresh (a zero frame), every pose 120 mm off
        ("  $TOOL = TOOL_DATA[1]\n", "  $TOOL = TOOL_DATA[2]\n"),
    ],
)
def test_a_kuka_pallet_program_reading_another_numbered_base_or_tool_fails_verify(testmat, old, new):
    mismatches = _mismatches(testmat, "kuka", "pal_testmat.src", old, new)
    assert mismatches, "the mutant passes verify"


@pytest.mark.slow  # a verify of the mutant: the slow set
def test_a_kuka_pallet_program_that_takes_its_frame_from_its_dat_again_fails_verify(testmat):
    """The program as it was: PAL_FRAME from its .dat (a regeneration writes the cell's nominal frame back over a
    measured one), no check of the base. Verify's base_not_measured case (BASE_DATA[1] as a fresh controller has it)
    expects the stop before any move; the old program moves."""
    program = next(p for p in sources(testmat, "kuka", "pallet"))
    (src,) = [f for f in program.files if f.name.endswith("pal_testmat.src")]
    start, end = src.text.index(BASE_CHECK_START), src.text.index(BASE_CHECK_END)
    mismatches = _mismatches(testmat, "kuka", "pal_testmat.src", src.text[start:end], "")
    assert mismatches and mismatches[0].startswith("base_not_measured"), mismatches


def _load(tmp_path, text: str):
    path = tmp_path / "cell.toml"
    path.write_text(text)
    return load_cell(path)


def test_a_numbered_base_beyond_the_controllers_or_shared_by_two_pallets_is_refused(tmp_path):
    text = (PALLETS / "eur_pallet.toml").read_text()
    assert "base_data = 2 " in text
    with pytest.raises(CellError, match=r"pallet\[1\]\.base_data: target kuka keeps bases 1\.\.32, got 33"):
        _load(tmp_path, text.replace("base_data = 2 ", "base_data = 33 ", 1))
    with pytest.raises(CellError, match=r"pallet\[1\]\.base_data: base 1 is pallet 'eur'.s already"):
        _load(tmp_path, text.replace("base_data = 2 ", "base_data = 1 ", 1))


def test_the_kuka_data_list_says_where_to_measure_the_pallet_frame(eur):
    """The .dat names the base to measure and the check: a test on the text (no simulation shows the pendant)."""
    files = _files(eur)
    dat = files["eur_pallet/kuka/pal_eur_in.dat"]
    assert "PAL_FRAME: the pallet frame as the program reads it at each start from BASE_DATA[2]" in dat
    assert "DECL FRAME PAL_NOMINAL={X 600.0000,Y -1100.0000,Z -500.0000," in dat
    src = files["eur_pallet/kuka/pal_eur_in.src"]
    assert "the tool is the controller's TOOL_DATA[1]" in src and "the controller's BASE_DATA[2]" in src


# (cell file, generated file, a text the commissioning engineer must find there): texts on the pendant or in the
# header that no simulation reaches (the operator reads them), each for a vendor finding
TEXTS = [
    # the release question tells the operator to take the item away before answering No (KRL, RAPID, URScript)
    ("testmat_pallet.toml", "testmat_pallet/kuka/pal_testmat.src", "Is the item down? No: remove it first"),
    ("testmat_pallet.toml", "testmat_pallet/abb/pal_testmat.mod", "Is the item down? No: remove it first"),
    ("testmat_pallet.toml", "testmat_pallet/ur/pal_testmat.script", "Is the item down? No: remove it first"),
    ("eur_pallet.toml", "eur_pallet/abb/pal_eur_in.mod", "Box back in its place? No: remove it first"),
    ("eur_pallet.toml", "eur_pallet/kuka/pal_eur_in.src", "Box back in its place? No: remove it first"),
    # an item held with the flag FALSE: another program's, or the store reloaded from its file
    ("eur_pallet.toml", "eur_pallet/abb/pal_eur.mod", "item held is another program's, or counters reloaded"),
    # the system module by automatic loading only (a module loaded by hand is gone after a reset of RAPID)
    ("eur_pallet.toml", "eur_pallet/abb/pallet_data.sys", "Automatic loading only: a module"),
    # a pallet program never returns: PP to main (ABB), select the other program (KUKA)
    ("eur_pallet.toml", "eur_pallet/abb/pallet_main.mod", "set the program pointer to main (PP to Main)"),
    ("eur_pallet.toml", "eur_pallet/kuka/pal_eur.src", "; The program never ends on its own"),
    # the configuration check off: to be checked in RobotStudio with the real robot's data
    ("eur_pallet.toml", "eur_pallet/abb/pal_eur.mod", "in RobotStudio with the real robot's data"),
    # the zone outputs follow the program, not the arm (the interlock is the controller's zones)
    ("eur_pallet.toml", "eur_pallet/abb/pal_eur.mod", "world zone (WZBoxDef, WZDOSet)"),
    ("eur_pallet.toml", "eur_pallet/kuka/pal_eur.src", "The zone outputs follow the program, not the arm"),
    # UR: the socket form in Remote Control, the node under Before Start, the log-only waits, set_tcp
    ("testmat_pallet.toml", "testmat_pallet/ur/pal_testmat.script", "in Remote Control only"),
    ("testmat_pallet.toml", "testmat_pallet/ur/pal_testmat_node.script", "put it under Before Start"),
    ("testmat_pallet.toml", "testmat_pallet/ur/pal_testmat.script", "in\n  # the log only"),
    ("testmat_pallet.toml", "testmat_pallet/ur/pal_testmat.script", "set_tcp makes the cell file's TCP the active one"),
]


@pytest.mark.parametrize(("cell_file", "path", "text"), TEXTS)
def test_the_programs_say_what_the_vendor_review_asked(cell_file, path, text):
    files = _files(load_cell(PALLETS / cell_file))
    assert text in files[path], f"{text!r} not in {path}"


def _checked_in_q(text: str, after: str, lift: str, check: str, end: str) -> tuple[str, str]:
    """(the unstacking program's lift from Q (the first after `after`, the release) with the pallet's check after it,
    the same with the check first: the arm still in Q's zone while it waits for the pallet)."""
    start = text.index(lift, text.index(after))
    middle = text.index(check, start)
    stop = text.index(end, middle)
    return text[start:stop], text[middle:stop] + text[start:middle]


@pytest.mark.slow  # a verify per target: the slow set
@pytest.mark.parametrize(
    ("target", "name", "after", "lift", "check", "end"),
    [
        (
            "kuka",
            "pal_eur_in.src",
            "    IF NOT PAL_RELEASE() THEN",
            "    LIN PAL_ABOVE ; exact: the pallet's check",
            "    IF PAL_EUR_IN_LAYER >= 1 THEN ; out of Q first",
            "    UP = TRUE\n",
        ),
        (
            "abb",
            "pal_eur_in.mod",
            "      ! the box is at Q: the next one (the layer's",
            "      MoveL stack_above_q, stack_work, fine, stack_tool;\n      ! out of the zone",
            "      IF pal_eur_in_layer >= 1 THEN\n        ! out of Q first",
            "      up_q := TRUE;\n",
        ),
    ],
)
def test_unstacking_leaves_q_before_it_checks_the_pallet(eur, target, name, after, lift, check, end):
    """After the release at Q the arm goes up out of Q's zone (its outputs reset), then waits for the pallet: the
    program that waits first (the arm in Q, the zone output on) fails the pallet_taken case (the pallet taken away
    after the grip), which expects the lift and the zone's outputs before the stop."""
    program = next(p for p in sources(eur, target, "pallet") if any(f.name.endswith(name) for f in p.files))
    (own,) = [f for f in program.files if f.name.endswith(name)]
    new, old = _checked_in_q(own.text, after, lift, check, end)
    mismatches = _mismatches(eur, target, name, new, old)
    assert mismatches and any(m.startswith("pallet_taken") for m in mismatches), mismatches
