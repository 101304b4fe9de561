"""The KRL check's walks kept per routine while the parse store keeps trees (what the language server does on each
edit): the findings after a series of edits equal a from-scratch `codegen check`'s, a routine whose text is unchanged
is checked again when a declaration it reads changes, and a .sub's findings without a line name the .sub."""

from __future__ import annotations

from pathlib import Path

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.kept import STORE
from codegen.dialects.krl import KRL
from codegen.dialects.krl.check import check_files
from codegen.lsp.diagnostics import by_file
from codegen.lsp.documents import Program

ROOT = Path(__file__).resolve().parents[2]
KUKA = ROOT / "generated" / "agv_machine_tending" / "kuka"
GOOD, BAD = "  VIS_STOPPED = FALSE", "  VIS_STOPED = FALSE"  # a line of the main routine of the generated .src

SRC = """DEF cell()
  DECL INT N
  N = A[5] + M
  P1 = {X 1.0}
  WAIT FOR DOOR
END
"""
DAT_STRUCTURE = """DEFDAT cell
DECL E6POS P1
SIGNAL DOOR $IN[3]
DECL INT A[3]
DECL INT M
ENDDAT
"""
DAT_SCALAR = """DEFDAT cell
DECL REAL P1
DECL BOOL DOOR=FALSE
DECL INT A[10]
DECL INT M=1
ENDDAT
"""


def _program(src: str, dat: str) -> list[SourceFile]:
    return [SourceFile("cell.src", src), SourceFile("cell.dat", dat)]


def _codes(findings) -> set[str]:
    return {f.code for f in findings}


def test_findings_after_edits_equal_a_fresh_check():
    src = (KUKA / "agv_machine_tending.src").read_text(encoding="utf-8")
    dat = (KUKA / "agv_machine_tending.dat").read_text(encoding="utf-8")
    assert GOOD in src and "DECL INT VIS_REQ=0" in dat
    edits = [  # (the .src, the .dat) in turn, as an editor sends them
        (src, dat),
        (src.replace(GOOD, BAD, 1), dat),
        (src.replace(GOOD, GOOD + "\n  X = 1 / 0", 1), dat),  # a line more: every later routine's lines move
        (src, dat.replace("DECL INT VIS_REQ=0", "DECL INT VIS_REQ", 1)),  # a data list's value gone
        (src.replace(GOOD, "  VIS_REQ = {X 1.0}", 1), dat),
        (src, dat),
    ]
    with STORE.keeping():
        kept = [check_files(_program(s, d)) for s, d in edits]
        assert STORE.results  # the walks' results are kept
    assert not STORE.results  # and let go with the trees
    fresh = [check_files(_program(s, d)) for s, d in edits]
    assert kept == fresh
    assert len({tuple(f) for f in fresh}) >= 4  # the edits change the findings


def test_a_changed_declaration_checks_the_unchanged_routine_again():
    with STORE.keeping():
        structure = check_files(_program(SRC, DAT_STRUCTURE))
        scalar = check_files(_program(SRC, DAT_SCALAR))
        back = check_files(_program(SRC, DAT_STRUCTURE))
    assert "type" not in _codes(structure) and "wait-without-timeout" in _codes(structure)
    assert "type" in _codes(scalar) and "wait-without-timeout" not in _codes(scalar)
    assert "index" in _codes(structure) and "index" not in _codes(scalar)
    assert any(f.message.startswith("M is read") for f in structure)
    assert not any(f.message.startswith("M is read") for f in scalar)
    assert back == structure


def test_a_sub_finding_without_a_line_lands_on_the_sub():
    sub = "DEF sps()\nEND\nDEF sps2()\nEND\nDEF sps2()\nEND\n"
    files = [SourceFile("cell.src", "DEF cell()\nEND\n"), SourceFile("sps.sub", sub)]
    findings = check_files(files)
    twice = [f for f in findings if "defined twice" in f.message]
    assert any(f.line == 0 for f in twice) and all(f.file == "sps.sub" for f in twice)
    shown = by_file(Program(KRL, tuple(files)), findings)
    assert [d.message for d in shown["sps.sub"]] == [f.message for f in twice]
    assert not any("defined twice" in d.message for d in shown["cell.src"])
