"""A restart question nobody answers: the program stops with its message after its time, the counters' mark kept,
and takes its dialog back (KUKA), rather than waiting at the pendant."""

from pathlib import Path

from support.programs import sources
from test_pallet_programs import mutant_mismatches

from codegen.model.cell import load_cell

PALLETS = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"


def test_a_kuka_question_without_its_time_limit_fails_verify():
    """The dialog polled without end (the program as it was) waits at the pendant in the unanswered case."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    found = mutant_mismatches(cell, "kuka", "pal_testmat.src", "IF POLLS >= PAL_ASK_POLLS THEN", "IF FALSE THEN")
    assert found and found[0].startswith("stopped_in_release"), found


def _ask_routine(text: str) -> list[str]:
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("DEFFCT INT PAL_ASK()"))
    end = next(i for i, line in enumerate(lines) if i > start and line.startswith("ENDFCT"))
    return [line.strip() for line in lines[start:end]]


def test_the_kuka_question_is_taken_back_before_the_unanswered_return():
    """No run sees a dialog left shown after the program stopped (the next start's Set_KrlDlg would get -1 and stop
    again): checked on the text, Clear_KrlMsg on the dialog's handle before the routine returns 0."""
    cell = load_cell(PALLETS / "testmat_pallet.toml")
    (own,) = [f for p in sources(cell, "kuka", "pallet") for f in p.files if f.name.endswith("pal_testmat.src")]
    body = _ask_routine(own.text)
    at = body.index("RETURN 0")
    assert any(line.startswith("CLEARED = CLEAR_KRLMSG(PAL_HANDLE)") for line in body[:at])
