"""The controllers' environment, the leftovers: KRL $PAL_MODE and MSGBUF_T, RAPID CDate; each as the interpreter models
it or refused by name (never "unknown type")."""

from __future__ import annotations

from click.testing import CliRunner

from codegen.cli import main


def _invoke(tmp_path, name: str, text: str, command: str = "run"):
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, [command, str(program)])


def test_krl_pal_mode_reads_off_and_switching_it_on_is_refused(tmp_path):
    """$PAL_MODE was an undefined variable."""
    text = "DEF pm()\nDECL BOOL P\nP = $PAL_MODE\n$PAL_MODE = FALSE\nIF NOT P THEN\n$PAL_MODE = TRUE\nENDIF\nEND\n"
    assert _invoke(tmp_path, "pm.src", text, "check").exit_code == 0
    result = _invoke(tmp_path, "pm.src", text)
    assert result.exit_code == 1, result.output
    assert "pm.src:6:1: $PAL_MODE = TRUE: palletizing mode (A4 held, the flange kept horizontal) is not modelled" in (
        result.stderr
    )


def test_krl_msgbuf_t_is_refused_by_name(tmp_path):
    """It was "unknown type MSGBUF_T", as if misspelt."""
    result = _invoke(tmp_path, "mb.src", "DEF mb()\nDECL MSGBUF_T B\nEND\n", "check")
    assert result.exit_code == 2, result.output
    assert "mb.src:2:6: unsupported: MSGBUF_T: the message buffer (Get_MsgBuffer) is not modelled" in result.output
    result = _invoke(tmp_path, "gm.src", "DEF gm()\nDECL INT N\nN = Get_MsgBuffer(N)\nEND\n", "check")
    assert result.exit_code == 2, result.output
    assert "Get_MsgBuffer (the message buffer) is not modelled" in result.output


def test_rapid_cdate_is_the_runs_date_and_a_string(tmp_path):
    """CDate was "not modelled"."""
    lines = "VAR string d;\nd := CDate();\nTPWrite d;\nWaitTime 86400;\nTPWrite CDate();"
    text = f"MODULE m\nPROC main()\n{lines}\nENDPROC\nENDMODULE\n"
    assert _invoke(tmp_path, "cd.mod", text, "check").exit_code == 0
    result = _invoke(tmp_path, "cd.mod", text)
    assert result.exit_code == 0, result.output
    assert "message: 2000-01-01" in result.output and "message: 2000-01-02" in result.output
    wrong = "MODULE m\nPROC main()\nVAR num d;\nd := CDate();\nENDPROC\nENDMODULE\n"
    result = _invoke(tmp_path, "wrong.mod", wrong, "check")
    assert result.exit_code == 2 and "the target is num, not string" in result.output
