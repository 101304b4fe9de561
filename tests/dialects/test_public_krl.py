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
