"""The handshakes at Q and at the slip-sheet dispenser: the arm-in-zone and done outputs, set with the arm standing
above the place, on every target; the programs without them (or with them set on the way) fail verify."""

from pathlib import Path

import pytest
from support.programs import edited, sources, verify_one

from codegen.model.cell import CellError, load_cell

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"


def _mismatches(cell_file: str, target: str, name: str, old: str, new: str) -> list:
    """The first mismatches of the program whose file `name` has `old` replaced by `new` (each occurrence)."""
    cell = load_cell(PALLETS / cell_file)
    program = next(p for p in sources(cell, target, "pallet") if any(f.name.endswith(name) for f in p.files))
    (own,) = [f for f in program.files if f.name.rsplit("/", 1)[-1] == name]
    assert old in own.text, f"{old!r} not in the {target} program's {name}"
    mutant = edited(program, lambda t: t.replace(old, new) if t == own.text else t)
    return verify_one(cell, mutant, first_mismatch=True, clearance=False).first_mismatches


# (cell, target, file, old, new, what the first mismatch says): the zone output taken out (the program as it was
# before the handshake), set only once the arm is down at Q, the move above Q blended again (the output then set
# while the arm moves), the done output never set, the zone left on after a stop
MUTATIONS = [
    (
        "testmat_pallet.toml",
        "ur",
        "pal_testmat.script",
        "      set_standard_digital_out(3, True)",
        "      #",
        "standard_digital_out[3]",
    ),
    (
        "testmat_pallet.toml",
        "ur",
        "pal_testmat.script",
        "      movel(PAL_ABOVE, a=1.2, v=0.0500)\n      set_standard_digital_out(3, False)",
        "      movel(PAL_ABOVE, a=1.2, v=0.0500, r=0.0020)\n      set_standard_digital_out(3, False)",
        "must stop exactly",
    ),
    (
        "testmat_pallet.toml",
        "ur",
        "pal_testmat.script",
        "  set_standard_digital_out(3, False)   # out of the pick place's zone",
        "  #",
        "standard_digital_out[3]",
    ),
    ("testmat_pallet.toml", "kuka", "pal_testmat.src", "      $OUT[23] = TRUE ;", "      ;", "$OUT[23] set to True"),
    (
        "testmat_pallet.toml",
        "kuka",
        "pal_testmat.src",
        "      $OUT[24] = TRUE ; (the arm stands",
        "      ; (the arm stands",
        "expected $OUT[24] set to True",
    ),
    ("testmat_pallet.toml", "abb", "pal_testmat.mod", "        SetDO doArmInQ, 1;\n", "", "doArmInQ set to True"),
    (
        "testmat_pallet.toml",
        "abb",
        "pal_testmat.mod",
        "        MoveL stack_above_q, stack_work, fine, stack_tool;\n        ! out of the zone",
        "        MoveL stack_above_q, stack_work, stack_zone, stack_tool;\n        ! out of the zone",
        "must stop exactly",
    ),
    (
        "testmat_pallet.toml",
        "abb",
        "pal_testmat.mod",
        "        SetDO doArmInQ, 1;\n        SetDO doPickDone, 0;\n"
        "        MoveL stack_q, stack_work, fine, stack_tool;\n",
        "        MoveL stack_q, stack_work, fine, stack_tool;\n"
        "        SetDO doArmInQ, 1;\n        SetDO doPickDone, 0;\n",
        "doArmInQ set to True after move",
    ),
    ("testmat_pallet.toml", "dtrans", "pal_testmat.prg", "    SetDO 4, True", "    //", "DO[4] set to True"),
    # the slip-sheet dispenser's handshake, and unstacking's place done at Q (the EUR cell)
    ("eur_pallet.toml", "abb", "pal_eur.mod", "          SetDO doArmInSheet, 1;\n", "", "doArmInSheet set to True"),
    (
        "eur_pallet.toml",
        "kuka",
        "pal_eur.src",
        "        LIN PAL_SHEET_ABOVE\n",
        "        LIN PAL_SHEET_ABOVE C_DIS\n",
        "must stop exactly",
    ),
    ("eur_pallet.toml", "kuka", "pal_eur_in.src", "    $OUT[29] = TRUE", "    ;", "expected $OUT[29] set to True"),
    ("eur_pallet.toml", "dtrans", "pal_eur_in.prg", "  SetDO 5, True", "  //", "DO[5] set to True"),
]


@pytest.mark.parametrize(("cell_file", "target", "name", "old", "new", "says"), MUTATIONS)
def test_a_program_without_its_handshake_at_a_standstill_fails_verify(cell_file, target, name, old, new, says):
    found = _mismatches(cell_file, target, name, old, new)
    assert found and says in found[0], found


def test_every_target_writes_the_handshake():
    assert {m[1] for m in MUTATIONS} == {"ur", "kuka", "abb", "dtrans"}


@pytest.mark.parametrize(
    ("given", "missing"),
    [
        ('q_zone = { ur = 3, kuka = 23, abb = "doArmInQ", dtrans = 4 }', r"io\.q_done: missing: q_zone and q_done"),
        (
            'sheet_zone = { ur = 5, kuka = 25, abb = "doZ", dtrans = 6 }\n'
            'sheet_taken = { ur = 6, kuka = 26, abb = "doT", dtrans = 7 }',
            r"io\.sheet_zone: the pallet places no slip sheets",
        ),
    ],
)
def test_a_handshake_comes_whole(tmp_path, given, missing):
    """The zone output and the done output are one handshake: one without the other is refused, naming the key; a
    sheet handshake needs slip sheets."""
    text = (PALLETS / "testmat_pallet.toml").read_text()
    text = text.replace("q_zone = { ur = 3,", "q_zone_old = { ur = 3,").replace("q_done = {", "q_done_old = {")
    text = "\n".join(line for line in text.splitlines() if not line.startswith(("q_zone_old", "q_done_old")))
    text = text.replace("timeout_s = 10.0", f"{given}\ntimeout_s = 10.0", 1)
    path = tmp_path / "cell.toml"
    path.write_text(text)
    with pytest.raises(CellError, match=missing):
        load_cell(path)


@pytest.mark.parametrize(
    ("old", "new"),
    [
        (" \\DIBreak:=diResetEur \\BreakFlag:=unanswered;", " \\BreakFlag:=unanswered;"),  # the question as it was
        ("IF unanswered <> ERR_TP_DIBREAK AND (unanswered <> 0 OR answer <> 1) THEN", "IF answer <> 1 THEN"),
    ],
)
def test_the_plcs_reset_while_the_operator_is_asked_answers_the_reloaded_store_question(old, new):
    """ABB: the counters' store reloaded from its file, the operator asked whether the pallet is new; the PLC's reset
    coming on meanwhile ends the question (TPReadFK \\DIBreak) and its handshake starts the pallet. A program whose
    question only the operator (or the 60 s) ends stops instead."""
    found = _mismatches("eur_pallet.toml", "abb", "pal_eur.mod", old, new)
    assert found and found[0].startswith("store_reloaded"), found


def test_the_ur_sheet_handshake_is_set_at_a_standstill(tmp_path):
    """No bundled UR cell places slip sheets: source 004's test cell with a sheet dispenser beside Q and its
    handshake. The UR program without the zone output going on before the sheet's pick fails verify."""
    text = (PALLETS / "testmat_pallet.toml").read_text()
    sheet = "slip_sheet = { every = 2, thickness = 1.0, pick = [560.0, 200.0, 50.0, 0.0, 0.0, 180.0], lift = 60.0 }"
    text = text.replace("zone_mm = 2.0 ", f"{sheet}\nzone_mm = 2.0 ", 1)
    io = (
        'sheet_ready = { ur = 5, kuka = 25, abb = "diSheetReady", dtrans = 6 }\n'
        'sheet_zone = { ur = 5, kuka = 25, abb = "doArmInSheet", dtrans = 6 }\n'
        'sheet_taken = { ur = 6, kuka = 26, abb = "doSheetTaken", dtrans = 7 }\n'
    )
    text = text.replace("timeout_s = 10.0\n", io + "timeout_s = 10.0\n", 1)
    path = tmp_path / "testmat_pallet.toml"
    path.write_text(text)
    cell = load_cell(path)
    program = next(
        p for p in sources(cell, "ur", "pallet") if any(f.name.endswith("pal_testmat.script") for f in p.files)
    )
    assert verify_one(cell, program, first_mismatch=True).first_mismatches == []
    on = "        set_standard_digital_out(5, True)   # into the zone"
    assert on in program.files[0].text
    found = verify_one(
        cell,
        edited(program, lambda t: t.replace(on, "        textmsg(0)   # into the zone")),
        first_mismatch=True,
        clearance=False,
    ).first_mismatches
    assert found and "standard_digital_out[5] set to True" in found[0], found
