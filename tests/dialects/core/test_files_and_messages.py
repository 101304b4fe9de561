"""The shared pieces of codegen check and of every message: decoding, findings from errors, operator errors."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects import get_dialect
from codegen.dialects.core.files import SourceFile, decode_text, finding_of
from codegen.dialects.core.values import RunError, describe, op_error


def test_decoding_names_the_file_and_the_byte():
    assert decode_text(b"\xef\xbb\xbfa\r\nb", "x.src", ("cp1252",)) == "a\nb"
    assert decode_text("Gr\u00fc\u00dfe".encode("cp1252"), "x.src", ("cp1252",)) == "Gr\u00fc\u00dfe"
    with pytest.raises(RunError, match=r"^x\.script: not UTF-8 text \(byte 1\)"):
        decode_text(b"a\xff", "x.script", ())
    with pytest.raises(RunError, match=r"^x\.src: byte 1 is not text in any encoding this controller uses"):
        decode_text(b"a\x81\x8d", "x.src", ("ascii",))


def test_a_finding_from_an_error_message():
    files = [SourceFile("dir/a b.mod", ""), SourceFile("c.mod", "")]
    found = finding_of("dir/a b.mod:12:5: Set is not modelled: no signals", files)
    assert (found.file, found.line, found.column, found.severity, found.code) == (
        "dir/a b.mod",
        12,
        5,
        "unsupported",
        "unsupported",
    )
    assert found.message == "Set is not modelled: no signals"
    syntax = finding_of("c.mod:3:1: syntax error at 'x', expected one of ';'", files, "load")
    assert (syntax.file, syntax.line, syntax.severity, syntax.code) == ("c.mod", 3, "error", "syntax")
    whole = finding_of("c.mod: cannot read", files)
    assert (whole.file, whole.line, whole.message) == ("c.mod", 0, "cannot read")
    assert whole.text() == "c.mod: error: cannot read [load]"


@pytest.mark.parametrize(
    ("operation", "said"),
    [
        (lambda: np.float32(1) + "a", "type mismatch (a number + a string)"),
        (lambda: "a" < 1, "type mismatch (a string < an integer)"),
        (lambda: -"a", "type mismatch (- of a string)"),
        (lambda: "a" + 1, "type mismatch (a string + an integer)"),
        (lambda: (lambda v: v[0])(None), "type mismatch (an index of no value)"),
        (lambda: int(float("nan")), "invalid value (not a number where an integer is needed)"),
        (lambda: 1 / 0, "division by zero"),
    ],
)
def test_operator_errors_in_the_programs_words(operation, said):
    with pytest.raises(Exception) as info:
        operation()
    assert str(op_error("f:1:1", info.value)) == f"f:1:1: {said}"


def test_a_values_kind():
    assert [describe(v) for v in (None, True, 3, np.float32(1.5), "s", [1])] == [
        "no value",
        "a boolean",
        "an integer",
        "a number",
        "a string",
        "an array",
    ]


def test_the_base_check_reports_a_syntax_error_of_every_file(tmp_path):
    one, two = tmp_path / "a.prg", tmp_path / "b.prg"
    one.write_text("Double a = 1 +\n")
    two.write_text("Double b = * 2\n")
    found = get_dialect("dtrans").check_files([SourceFile(str(one), one.read_text())])
    assert [(f.line, f.code) for f in found] == [(1, "syntax")]
    result = CliRunner().invoke(main, ["check", str(one), str(two)])
    assert result.exit_code == 2 and "a.prg:1:" in result.output and "b.prg:1:" in result.output, result.output


def test_check_of_a_data_file_alone_is_a_finding(tmp_path):
    data = tmp_path / "t.dat"
    data.write_text("DEFDAT T\nENDDAT\n")
    result = CliRunner().invoke(main, ["check", str(data)])
    assert result.exit_code == 2 and "t.dat" in result.output, result.output


def test_check_takes_the_programs_of_several_controllers_at_once():
    from pathlib import Path

    demo = Path(__file__).resolve().parents[3] / "generated" / "agv_machine_tending"
    result = CliRunner().invoke(main, ["check", str(demo), "--json"])
    data = json.loads(result.output)
    assert result.exit_code == 0 and data["targets"] == ["abb", "dtrans", "kuka", "ur"], result.output
    assert len(data["programs"]) == 5 and data["findings"] == []
