"""KRL dialogs: Set_KrlDlg shows a dialog with softkeys, Exists_KrlDlg polled until the run's operator answers."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.sim.operator import Operator

from .helpers import program

DECLS = "DECL KRLMSG_T MSG\nDECL KRLMSGPAR_T PAR[3]\nDECL KRLMSGDLGSK_T KEY[{keys}]\nDECL KRLMSGOPT_T OPT\nDECL INT I"
DAT = "DECL INT H, ANSWER, POLLS, SECOND\n"


def _body(yes: str = "Yes", keys: int = 7, call: str = "H = SET_KRLDLG(MSG, PAR[], KEY[], OPT)") -> str:
    return f"""MSG = {{MODUL[] "T", NR 1, MSG_TXT[] "write tool %1?"}}
PAR[1] = {{PAR_TYPE #VALUE, PAR_INT 3}}
PAR[2] = {{PAR_TYPE #EMPTY}}
PAR[3] = {{PAR_TYPE #EMPTY}}
KEY[1] = {{SK_TYPE #VALUE, SK_TXT[] "{yes}"}}
KEY[2] = {{SK_TYPE #VALUE, SK_TXT[] "No"}}
FOR I = 3 TO {keys}
  KEY[I] = {{SK_TYPE #EMPTY}}
ENDFOR
OPT = {{VL_STOP TRUE, CLEAR_P_RESET TRUE, CLEAR_P_SAW FALSE, LOG_TO_DB FALSE}}
ANSWER = -5
POLLS = 0
{call}
WHILE EXISTS_KRLDLG(H, ANSWER)
  POLLS = POLLS + 1
  WAIT SEC 0.1
ENDWHILE
MsgNotify("answered")"""


def _run(answers=None, keys: int = 7, **kw):
    devices = () if answers is None else (Operator(answers),)
    loaded = program(_body(keys=keys, **kw), DECLS.format(keys=keys), DAT)
    return loaded.run({}, devices=devices, keep=("H", "ANSWER", "POLLS", "SECOND"))


@pytest.mark.parametrize(("answer", "key"), [("No", 2), ("yes", 1), (2, 2), ("1", 1)])
def test_the_operator_answers_a_dialog_by_a_softkey_s_number_or_label(answer, key):
    trace = _run([answer])
    assert trace.messages == ["write tool 3?", "answered"]  # the dialog's text, its parameter in it
    # Exists_KrlDlg: TRUE while the dialog is shown (the operator reads it), then FALSE with the softkey's number
    assert trace.kept["ANSWER"] == key and trace.kept["POLLS"] == 1 and trace.kept["H"] > 0


def test_a_dialog_nobody_answers_stops_the_run_naming_the_line():
    with pytest.raises(RunError, match=r"t\.src:20:7: Exists_KrlDlg: the dialog 'write tool 3\?' waits for the"):
        _run()
    with pytest.raises(RunError, match=r"t\.src:20:7: Exists_KrlDlg: .* not a softkey shown \(1 Yes, 2 No\)"):
        _run([3])


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"keys": 6}, r"t\.src:19:5: Set_KrlDlg: the softkeys is a KRLMSGDLGSK_T\[7\], got 6 elements"),
        ({"yes": "Yes, write it"}, r"t\.src:19:5: Set_KrlDlg: softkey 1: Sk_Txt is CHAR\[10\]"),
        ({"call": "H = SET_KRLDLG(PAR[1], PAR[], KEY[], OPT)"}, r"t\.src:19:5: Set_KrlDlg: the message is a KRLMSG_T"),
        ({"call": "H = SET_KRLDLG(MSG, KEY[], KEY[], OPT)"}, r"Set_KrlDlg: the parameters is an array of KRLMSGPAR_T"),
        ({"call": "H = SET_KRLDLG(MSG, PAR[], KEY[], MSG)"}, r"t\.src:19:5: Set_KrlDlg: the options is a KRLMSGOPT_T"),
    ],
)
def test_set_krldlg_checks_its_parameters_types_and_sizes(options, message):
    with pytest.raises(RunError, match=message):
        _run(["Yes"], **options)


def test_out_parameters_take_variables_only():
    with pytest.raises(RunError, match=r"EXISTS_KRLDLG: argument 2 is OUT: give a variable"):
        program("H = 1\nWHILE EXISTS_KRLDLG(H, 2)\nENDWHILE", "", DAT)


def test_a_second_dialog_while_one_is_shown_is_not_generated_and_an_unknown_handle_is_gone():
    call = "H = SET_KRLDLG(MSG, PAR[], KEY[], OPT)\nSECOND = SET_KRLDLG(MSG, PAR[], KEY[], OPT)"
    trace = _run(["No"], call=call)
    assert trace.kept["SECOND"] == -1 and trace.kept["ANSWER"] == 2
    assert trace.messages == ["write tool 3?", "answered"]  # shown once
    trace = _run(["No"], call="H = -1")  # no dialog has that handle: FALSE at once, the answer 0
    assert trace.kept["ANSWER"] == 0 and trace.kept["POLLS"] == 0


def test_codegen_run_answers_a_dialog_with_the_answers_given(tmp_path):
    from click.testing import CliRunner

    from codegen.cli import main

    src = f'DEF T()\n{DECLS.format(keys=7)}\n{_body()}\nMsgNotify("done")\nEND\n'
    (tmp_path / "t.src").write_text(src)
    (tmp_path / "t.dat").write_text(f"DEFDAT T\n{DAT}ENDDAT\n")
    runner = CliRunner()
    answered = runner.invoke(main, ["run", str(tmp_path / "t.src"), "--answer", "No"])
    assert answered.exit_code == 0, answered.output
    assert "message: write tool 3?" in answered.output and "message: done" in answered.output
    waiting = runner.invoke(main, ["run", str(tmp_path / "t.src")])
    assert waiting.exit_code == 1 and "no operator answers in this run (codegen run --answer)" in waiting.output
    assert "Traceback" not in waiting.output


def test_a_dialog_nobody_answers_is_taken_back_with_clear_krlmsg():
    """An operator who looks away: the dialog stays shown while the program polls; Clear_KrlMsg deletes it (TRUE),
    Exists_KrlDlg then answers FALSE with 0, and another dialog can be shown again."""
    timed = (
        "H = SET_KRLDLG(MSG, PAR[], KEY[], OPT)\n"
        "WHILE EXISTS_KRLDLG(H, ANSWER) AND (POLLS < 30)\n  POLLS = POLLS + 1\n  WAIT SEC 0.1\nENDWHILE\n"
        "SECOND = SET_KRLDLG(MSG, PAR[], KEY[], OPT)\n"  # the first still shown: -1
        "IF CLEAR_KRLMSG(H) THEN\n  SECOND = SET_KRLDLG(MSG, PAR[], KEY[], OPT)\nENDIF\n"
        "POLLS = 0\nH = SECOND\nIF NOT CLEAR_KRLMSG(SECOND) THEN\n  H = -1\nENDIF"
    )
    loaded = program(_body(call=timed), DECLS.format(keys=7), DAT)
    trace = loaded.run({}, devices=(Operator([], then_silent=True),), keep=("H", "ANSWER", "POLLS", "SECOND"))
    assert trace.kept["SECOND"] > 0 and trace.kept["H"] == trace.kept["SECOND"]  # shown once the first was cleared
    assert trace.clock == pytest.approx(3.0, abs=0.2) and trace.kept["ANSWER"] == 0  # the second cleared: 0
    cleared = program(
        _body(call="H = SET_KRLDLG(MSG, PAR[], KEY[], OPT)\nI = 0\nIF CLEAR_KRLMSG(H) THEN\n  I = 1\nENDIF"),
        DECLS.format(keys=7),
        DAT,
    ).run({}, keep=("H", "ANSWER", "POLLS"))
    assert cleared.kept["ANSWER"] == 0 and cleared.kept["POLLS"] == 0  # deleted: FALSE at once, the answer 0
