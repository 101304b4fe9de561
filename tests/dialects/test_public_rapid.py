"""RAPID as others write it: WaitGI / WaitGO (group signals' waits) and signals spelt gI_..., dO_... Programs
written here for the test, not taken from the public ones."""

from __future__ import annotations

from click.testing import CliRunner

from codegen.cli import main


def _invoke(tmp_path, text: str, command: str = "run"):
    program = tmp_path / "groups.mod"
    program.write_text(f"MODULE groups\nPROC main()\n{text}\nENDPROC\nENDMODULE\n", encoding="utf-8")
    return CliRunner().invoke(main, [command, str(program)])


def test_group_waits_compare_the_groups_number(tmp_path):
    """WaitGI and WaitGO were "not modelled by the interpreter"."""
    text = (
        "  VAR bool late;\n"
        "  SetGO go_recipe, 5;\n"
        "  WaitGO go_recipe, 5;\n"
        "  WaitGO go_recipe, \\GT, 4;\n"
        "  WaitGO go_recipe, \\LT, 6 \\MaxTime:=1;\n"
        '  TPWrite "output waits passed";\n'
        "  WaitGI gi_state, \\NOTEQ, 3 \\MaxTime:=1;\n"
        '  TPWrite "input is not 3";\n'
        "  WaitGI gi_state, 3 \\MaxTime:=2 \\TimeFlag:=late;\n"
        "  IF late THEN\n"
        '    TPWrite "no 3 within 2 s";\n'
        "  ENDIF\n"
        "  WaitGO go_recipe, \\NOTEQ, 5 \\MaxTime:=0.5;"
    )
    checked = _invoke(tmp_path, text, "check")
    assert checked.exit_code == 0, checked.output
    result = _invoke(tmp_path, text)
    assert "message: output waits passed\nmessage: input is not 3\nmessage: no 3 within 2 s" in result.output
    assert "ERR_WAIT_MAXTIME: " in result.output and "groups.mod:15:3: WaitGO \\MaxTime 0.5 s passed" in result.output


def test_group_wait_takes_one_comparison_and_a_whole_number(tmp_path):
    two = _invoke(tmp_path, "  WaitGI gi_state, \\LT, 3 \\GT;", "check")
    assert two.exit_code == 2 and "WaitGI takes one of \\NOTEQ, \\LT and \\GT" in two.output
    half = _invoke(tmp_path, "  WaitGI gi_state, 2.5 \\MaxTime:=1;")
    assert half.exit_code == 1 and "WaitGI gi_state: 2.5 is not a whole number" in half.stderr, half.output
    digital = _invoke(tmp_path, "  WaitDI di_part, 1, \\NOTEQ;", "check")
    assert digital.exit_code == 2 and "WaitDI has no argument \\NOTEQ" in digital.output, digital.output


def test_signals_spelt_with_a_mixed_case_prefix_are_the_io_configurations(tmp_path):
    """`IF gI_ProgNum = 1` was "undefined variable gI_ProgNum" (di_, DI_, diName were taken, gI_ was not)."""
    text = '  IF gI_ProgNum = 0 AND dI_Ready = 0 THEN\n    TPWrite "idle";\n  ENDIF'
    checked = _invoke(tmp_path, text, "check")
    assert checked.exit_code == 1, checked.output  # warnings: a guess, said so
    assert "gI_ProgNum is not declared: taken as the group input gI_ProgNum" in checked.output
    assert "dI_Ready is not declared: taken as the digital input dI_Ready" in checked.output
    result = _invoke(tmp_path, text)
    assert result.exit_code == 0 and "message: idle" in result.output, result.output
