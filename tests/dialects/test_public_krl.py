"""KRL as others write it: the technology packages' types refused by name (never "unknown type"). Programs
written here for the test, not taken from the public ones."""

from __future__ import annotations

from click.testing import CliRunner

from codegen.cli import main


def test_technology_package_types_are_refused_by_name(tmp_path):
    """`DECL GRP_TYP ...` in a data list was "unknown type GRP_TYP", as if misspelt."""
    (tmp_path / "grip.src").write_text("DEF grip()\nWAIT SEC 0.1\nEND\n", encoding="utf-8")
    for name in ("GRP_TYP", "SPOT_TYPE", "S_COMMAND"):
        (tmp_path / "grip.dat").write_text(f"DEFDAT grip\nDECL {name} SETTING\nENDDAT\n", encoding="utf-8")
        result = CliRunner().invoke(main, ["check", str(tmp_path / "grip.src")])
        assert result.exit_code == 2, result.output
        assert f"grip.dat:2:6: unsupported: {name}: a type of KUKA's technology packages" in result.output
        assert "unknown type" not in result.output


def test_a_data_lists_global_signal_is_every_modules(tmp_path):
    """`GLOBAL SIGNAL name $OUT[n]` in a PUBLIC data list was a syntax error at SIGNAL."""
    (tmp_path / "io.dat").write_text(
        "DEFDAT io PUBLIC\nGLOBAL SIGNAL lamp $OUT[5]\nGLOBAL SIGNAL speed $OUT[10] TO $OUT[13]\n"
        "GLOBAL SIGNAL ready $IN[2]\nSIGNAL own $OUT[7]\nENDDAT\n",
        encoding="utf-8",
    )
    cell = tmp_path / "cell.src"
    cell.write_text(
        "DEF cell()\nlamp = TRUE\nspeed = 11\nIF ready THEN\nlamp = FALSE\nENDIF\nPULSE(lamp, FALSE, 0.5)\nEND\n",
        encoding="utf-8",
    )
    files = [str(cell), str(tmp_path / "io.dat")]
    checked = CliRunner().invoke(main, ["check", *files])
    assert checked.exit_code == 0, checked.output
    result = CliRunner().invoke(main, ["run", *files])
    assert result.exit_code == 0, result.output
    # 11 = 1011 in binary: $OUT[10], [11] and [13] on, [12] off; the input is off, so the lamp stays on until
    # the pulse turns it off for 0.5 s
    for line in (
        "output (line 2): $OUT[5] = on",
        "output (line 3): $OUT[10] = on",
        "output (line 3): $OUT[11] = on",
        "output (line 3): $OUT[13] = on",
        "output (line 7): $OUT[5] = off at 0.000 s",
        "output (line 7): $OUT[5] = on at 0.500 s",
    ):
        assert line in result.output, result.output
    assert "$OUT[12] = on" not in result.output
    cell.write_text("DEF cell()\nown = TRUE\nEND\n", encoding="utf-8")  # a SIGNAL without GLOBAL: io.dat's own
    hidden = CliRunner().invoke(main, ["check", *files])
    assert hidden.exit_code == 2 and "cell.src:2:1: error: undefined variable own" in hidden.output, hidden.output
